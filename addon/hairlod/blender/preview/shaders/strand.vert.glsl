/* A strand drawn as lines, one vertex per control point (object space). */
void main()
{
  gl_Position = view_projection * vec4(position, 1.0);
  v_tangent = normalize(tangent);
  v_to_camera = camera.xyz - position * camera.w;
  v_across = 0.0;
  v_ellipse = vec3(0.0);
  v_cluster = vec2(1.0, 1.0);
}
