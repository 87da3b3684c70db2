/* A strand drawn as lines, one vertex per control point; the rest pose in object space in, skinned
 * to the current frame (skinning.glsl), world space out. */
void main()
{
  ivec2 cluster_point = ivec2(select_key + 0.5);
  mat3 skin;
  vec3 world = (frame.model * vec4(skin_point(cluster_point, position, skin), 1.0)).xyz;
  gl_Position = frame.view_projection * vec4(world, 1.0);
  v_position = world;
  v_tangent = normalize(mat3(frame.model) * (skin * tangent));
  v_to_camera = frame.camera.xyz - world * frame.camera.w;
  v_across = 0.0;
  v_ellipse = vec3(0.0);
  v_widen = 1.0;
  v_cluster = vec2(1.0, 1.0);  /* one hair: n = 1, rho = 1 */
  v_select_cluster = int(select_key.x + 0.5);
  v_select_point = select_key.y;
}
