/* A strand drawn as lines, one vertex per control point; the rest pose in object space in, skinned
 * to the current frame (skinning.glsl), world space out. What a thick hair's varyings hold is
 * constant along a strand (lod_preview.STRAND_CONSTANTS), and the selection's key goes out only where
 * the fragments test it. */
void main()
{
  ivec2 cluster_point = ivec2(select_key + 0.5);
  mat3 skin;
  vec3 world = (frame.model * vec4(skin_point(cluster_point, position, skin), 1.0)).xyz;
  gl_Position = frame.view_projection * vec4(world, 1.0);
  v_position = world;
  v_tangent = normalize(mat3(frame.model) * (skin * tangent));
#ifndef HAIRLOD_ALL_AT_DRAW_LEVEL
  v_select_cluster = int(select_key.x + 0.5);
  v_select_point = select_key.y;
#endif
}
