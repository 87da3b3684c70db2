/* A strand drawn as lines, one vertex per control point; the rest pose in object space in, skinned
 * to the current frame (skinning.glsl), world space out. What a thick hair's varyings hold is
 * constant along a strand (lod_preview.STRAND_CONSTANTS), and the selection's key goes out only where
 * the fragments test it.
 *
 * Strands by coverage (frame.counts.z = 1): a line is a pixel wide, a strand often a fifth of that, so
 * drawing every strand covers several times the pixels the hair covers (4.4-4.9x on the real Ratboy
 * mohawk against its path-traced coverage). Each strand is drawn with the probability of its width in
 * pixels (coverage_choice.glsl), the lines whole and opaque. The width is taken once per L0 cluster, at
 * its middle control point, so that every vertex of a strand decides alike; frame.counts.y is the
 * control points per strand, frame.shadow.x the strands' radius in world units. */

/* The width in pixels of a strand of L0 cluster `cluster`, at the cluster's skinned origin at its middle
 * control point (skinning.glsl: texels 1-3 hold the map's origin in w). */
float strand_width_px(int cluster)
{
  ivec2 middle = ivec2(cluster, int(frame.counts.y) / 2);
  vec3 origin = vec3(skin_texel(middle, 1).w, skin_texel(middle, 2).w, skin_texel(middle, 3).w);
  vec3 world = (frame.model * vec4(origin, 1.0)).xyz;
  vec3 view = frame.camera.w > 0.5 ? world - frame.camera.xyz : -frame.camera.xyz;
  vec3 side = cross(view, abs(view.z) < 0.9 * length(view) ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0));
  vec4 clip = frame.view_projection * vec4(world, 1.0);
  vec4 clip_side = frame.view_projection * vec4(normalize(side), 0.0);
  if (clip.w <= 0.0) {
    return 1.0;
  }
  return 2.0 * frame.shadow.x * length(clip_side.xy * 0.5 * frame.viewport.xy) / clip.w;
}

/* The strand's point moved rigidly with its root triangle (hair attached to a mesh, frame.counts.w = 1;
 * blender/surface.py): the rows of strand `item`'s map [R | t] in strand_frames, SURFACE_ROW strands a
 * row, and R for its tangents. */
vec3 surface_point(int item, vec3 rest, out mat3 rotation)
{
  ivec2 first = ivec2(3 * (item % SURFACE_ROW), item / SURFACE_ROW);
  vec4 rows[3];
  for (int r = 0; r < 3; ++r) {
    rows[r] = texelFetch(strand_frames, first + ivec2(r, 0), 0);
  }
  rotation = mat3(rows[0].x, rows[1].x, rows[2].x, rows[0].y, rows[1].y, rows[2].y, rows[0].z, rows[1].z, rows[2].z);
  return vec3(dot(rows[0], vec4(rest, 1.0)), dot(rows[1], vec4(rest, 1.0)), dot(rows[2], vec4(rest, 1.0)));
}

void main()
{
  ivec2 cluster_point = ivec2(select_key + 0.5);
  mat3 skin;
  vec3 moved = frame.counts.w > 0.5 ? surface_point(gl_VertexID / int(frame.counts.y), position, skin)
                                    : skin_point(cluster_point, position, skin);
  vec3 world = (frame.model * vec4(moved, 1.0)).xyz;
  gl_Position = frame.view_projection * vec4(world, 1.0);
  if (frame.counts.z > 0.5 && !drawn_by_coverage(uint(gl_VertexID) / uint(frame.counts.y), strand_width_px(cluster_point.x))) {
    gl_Position = vec4(0.0, 0.0, -2.0, 1.0);  /* every vertex of the strand, behind the near plane: not drawn */
  }
  v_position = world;
  v_tangent = normalize(mat3(frame.model) * (skin * tangent));
#ifndef HAIRLOD_ALL_AT_DRAW_LEVEL
  v_select_cluster = int(select_key.x + 0.5);
  v_select_point = select_key.y;
#endif
}
