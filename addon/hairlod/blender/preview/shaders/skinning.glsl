/* Linear skinning on the GPU (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 4): the vertex buffers
 * hold the rest pose, and every point of L0 cluster c at control point k moves by that cluster's
 * affine map there, p' = M p + t, from hairlod.lod.FrameSkinning: 3 texels per map in skin_maps,
 * row r of [M | t] at texel (3 k + r, c). Rest vectors (cross-section axes, tangents) map by M.
 * A tangent mapped by M is the skinned curve's tangent under rigid motion and follows a smooth
 * bend to first order; positions are exact for any deformation. */
vec4 skin_row(ivec2 cluster_point, int row)
{
  return texelFetch(skin_maps, ivec2(3 * cluster_point.y + row, cluster_point.x), 0);
}

vec3 skin_point(ivec2 cluster_point, vec3 rest)
{
  vec4 p = vec4(rest, 1.0);
  return vec3(dot(skin_row(cluster_point, 0), p), dot(skin_row(cluster_point, 1), p),
              dot(skin_row(cluster_point, 2), p));
}

mat3 skin_linear(ivec2 cluster_point)
{
  vec4 r0 = skin_row(cluster_point, 0), r1 = skin_row(cluster_point, 1), r2 = skin_row(cluster_point, 2);
  /* GLSL matrices are built column by column. */
  return mat3(r0.x, r1.x, r2.x, r0.y, r1.y, r2.y, r0.z, r1.z, r2.z);
}
