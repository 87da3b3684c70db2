/* Camera-facing strip of a thick elliptical hair (hair-lod-aggregated-bcsdf.txt Sec. 5): vertices
 * 2k and 2k + 1 sit on either side of control point k. The strip spans the ellipse's silhouette seen
 * from the camera, so a switch between levels keeps the drawn width; at least half a pixel either
 * side so that thin hairs do not fall between pixels. Inputs are the rest pose in object space,
 * skinned to the current frame (skinning.glsl); outputs in world space (frame.model is the
 * object's matrix). */
void main()
{
  ivec2 cluster_point = ivec2(select_key + 0.5);
  mat3 skin;
  vec3 world = (frame.model * vec4(skin_point(cluster_point, position, skin), 1.0)).xyz;
  mat3 linear = mat3(frame.model);
  vec3 t = normalize(linear * (skin * tangent));
  vec3 major_w = linear * (skin * major), minor_w = linear * (skin * minor);
  vec3 to_camera = frame.camera.xyz - world * frame.camera.w;
  vec3 side = cross(t, to_camera);
  float side_length = length(side);
  side = side_length > 1e-20 ? side / side_length : normalize(major_w + 1e-20);
  /* Silhouette half-width of the ellipse with semi-axes major, minor across `side`. */
  float half_width = length(vec2(dot(major_w, side), dot(minor_w, side)));

  vec4 clip_centre = frame.view_projection * vec4(world, 1.0);
  vec4 clip_side = frame.view_projection * vec4(side, 0.0);
  float pixels_per_unit = length(clip_side.xy * 0.5 * frame.viewport.xy) / max(abs(clip_centre.w), 1e-20);
  float drawn_half_width = max(half_width, 0.5 / max(pixels_per_unit, 1e-20));

  float across = (gl_VertexID & 1) == 0 ? -1.0 : 1.0;
  gl_Position = clip_centre + across * drawn_half_width * clip_side;

  v_position = world + across * drawn_half_width * side;
  v_tangent = t;
  v_to_camera = to_camera;
  /* The fragment's offset across the true silhouette, in [-1, 1] inside it. */
  v_across = across * drawn_half_width / max(half_width, 1e-20);
  v_ellipse = vec3(length(major_w), length(minor_w), half_width);
  v_widen = drawn_half_width / max(half_width, 1e-20);
  v_cluster = cluster;
#ifndef HAIRLOD_ALL_AT_DRAW_LEVEL
  v_select_cluster = int(select_key.x + 0.5);
  v_select_point = select_key.y;
#endif
}
