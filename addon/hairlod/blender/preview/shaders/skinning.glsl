/* Skinning on the GPU (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 4): the vertex buffers hold the
 * rest pose, and every point of L0 cluster c at control point k moves by that cluster's quadratic
 * map there (hairlod.lod.FrameSkinning, cpp/include/hairlod/lod/skinning.h: map_texels): with
 * d = p - rest origin, p'_r = dot(linear row r, d) + origin_r + sum of the second-order terms.
 * SKIN_MAP_TEXELS texels per map in skin_maps, texel t of map (c, k) at (SKIN_MAP_TEXELS k + t, c):
 * 0 the rest origin, 1-3 (linear row r, origin r), 4-6 row r's coefficients of (dx^2, dy^2, dz^2),
 * 7-9 of (dx dy, dy dz, dz dx). Rest vectors there (cross-section axes, tangents) map by the
 * Jacobian at the point: the skinned curve's tangent to first order. */
vec4 skin_texel(ivec2 cluster_point, int texel)
{
  return texelFetch(skin_maps, ivec2(SKIN_MAP_TEXELS * cluster_point.y + texel, cluster_point.x), 0);
}

/* The skinned point of `rest`, and the map's Jacobian there. */
vec3 skin_point(ivec2 cluster_point, vec3 rest, out mat3 jacobian)
{
  vec3 d = rest - skin_texel(cluster_point, 0).xyz;
  vec4 row[3];
  vec3 squares[3], products[3];
  for (int r = 0; r < 3; ++r) {
    row[r] = skin_texel(cluster_point, 1 + r);
    squares[r] = skin_texel(cluster_point, 4 + r).xyz;
    products[r] = skin_texel(cluster_point, 7 + r).xyz;
  }
  vec3 d2 = d * d, dd = vec3(d.x * d.y, d.y * d.z, d.z * d.x);
  vec3 skinned;
  for (int r = 0; r < 3; ++r) {
    skinned[r] = dot(row[r], vec4(d, 1.0)) + dot(squares[r], d2) + dot(products[r], dd);
  }
  /* Rows of the Jacobian: the linear row plus the gradient of the second-order terms. */
  vec3 gradient[3];
  for (int r = 0; r < 3; ++r) {
    vec3 s = squares[r], p = products[r];
    gradient[r] = row[r].xyz + vec3(2.0 * s.x * d.x + p.x * d.y + p.z * d.z,
                                    2.0 * s.y * d.y + p.x * d.x + p.y * d.z,
                                    2.0 * s.z * d.z + p.y * d.y + p.z * d.x);
  }
  /* GLSL matrices are built column by column. */
  jacobian = mat3(gradient[0].x, gradient[1].x, gradient[2].x, gradient[0].y, gradient[1].y, gradient[2].y,
                  gradient[0].z, gradient[1].z, gradient[2].z);
  return skinned;
}
