/* Camera-facing strip of a thick elliptical hair (hair-lod-aggregated-bcsdf.txt Sec. 5): vertices
 * 2k and 2k + 1 sit on either side of control point k (`across` -1 and +1). The strip spans the ellipse's silhouette seen
 * from the camera, so a switch between levels keeps the drawn width; at least half a pixel either
 * side so that thin hairs do not fall between pixels. Inputs are the rest pose in object space,
 * skinned to the current frame (skinning.glsl); outputs in world space (frame.model is the
 * object's matrix).
 *
 * By coverage (frame.counts.z = 1, as the strands, coverage_choice.glsl): a sparse thick hair covers
 * only part of its strip, where a camera ray meets one of its strands, as the path tracer's thick
 * hairs let the rays between their strands through. Each control point keeps its width in the samples
 * where hair `hair` is drawn at the strip's coverage there (strip_coverage), and narrows to its centre
 * line in the others: a segment between a kept and a narrowed point is half drawn, so the strip's
 * expected area follows the coverage along it. */

/* The share of a strip of half-width w that the camera rays meeting a strand cover: the hair's N strands
 * of radius r spread over the ellipse's silhouette as its chords are (opacity_map.py's
 * thick_hair_coverage), so a ray at x in [-1, 1] across crosses tau(x) = tau0 sqrt(1 - x^2) strands on
 * average, tau0 = 4 r N / (pi w), and meets one with probability 1 - exp(-tau(x)) (Poisson). The mean
 * over x, with x = sin(phi): the integral over [0, pi/2] of (1 - exp(-tau0 cos phi)) cos phi, by 4-point
 * Gauss-Legendre (tau0 pi / 4 for sparse hairs, 1 for dense ones). */
#ifndef HAIRLOD_PI
#define HAIRLOD_PI 3.14159265358979
#endif
float strip_coverage(float tau0)
{
  const vec4 nodes = vec4(0.0694318442, 0.3300094782, 0.6699905218, 0.9305681558) * (0.5 * HAIRLOD_PI);
  const vec4 weights = vec4(0.1739274226, 0.3260725774, 0.3260725774, 0.1739274226) * (0.5 * HAIRLOD_PI);
  vec4 c = cos(nodes);
  return dot(weights, (vec4(1.0) - exp(-tau0 * c)) * c);
}

void thick_vertex(vec3 rest_position, vec3 rest_tangent, vec3 rest_major, vec3 rest_minor, vec2 hair_cluster,
                  vec2 key, float across, uint hair)
{
  ivec2 cluster_point = ivec2(key + 0.5);
  mat3 skin;
  vec3 world = (frame.model * vec4(skin_point(cluster_point, rest_position, skin), 1.0)).xyz;
  mat3 linear = mat3(frame.model);
  vec3 t = normalize(linear * (skin * rest_tangent));
  vec3 major_w = linear * (skin * rest_major), minor_w = linear * (skin * rest_minor);
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
  if (frame.counts.z > 0.5) {
    float tau0 = 4.0 * frame.shadow.x * hair_cluster.x / (HAIRLOD_PI * drawn_half_width);
    if (!drawn_by_coverage(hair, strip_coverage(tau0))) {
      drawn_half_width = 0.0;
    }
  }

  gl_Position = clip_centre + across * drawn_half_width * clip_side;

  v_position = world + across * drawn_half_width * side;
  v_tangent = t;
  v_to_camera = to_camera;
  /* The fragment's offset across the true silhouette, in [-1, 1] inside it. */
  v_across = across * drawn_half_width / max(half_width, 1e-20);
  v_ellipse = vec3(length(major_w), length(minor_w), half_width);
  v_widen = drawn_half_width / max(half_width, 1e-20);
  v_cluster = hair_cluster;
#ifndef HAIRLOD_ALL_AT_DRAW_LEVEL
  v_select_cluster = int(key.x + 0.5);
  v_select_point = key.y;
#endif
}

#ifdef HAIRLOD_PULLED
/* A sparse level's selected segments without an index list (hairlod/pulled_strips.py): vertex
 * 4s + 2c + side of slot s is control point c of the slot's segment, whose first point is texel s of
 * pulled_segments (its low and high 16 bits); each point's attributes are POINT_TEXELS texels of pulled_points. Slots past
 * pulled_count collapse beyond the far plane, where their triangles are clipped. */
vec4 point_texel(int point, int texel)
{
  return texelFetch(pulled_points, ivec2(POINT_TEXELS * (point % POINT_ROW) + texel, point / POINT_ROW), 0);
}

void main()
{
  int slot = slot_vertex >> 2;
  if (slot >= pulled_count) {
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    v_position = vec3(0.0);
    v_tangent = vec3(0.0);
    v_to_camera = vec3(0.0);
    v_ellipse = vec3(0.0);
    v_across = 0.0;
    v_widen = 0.0;
    v_cluster = vec2(0.0);
    return;
  }
  ivec2 start = ivec2(texelFetch(pulled_segments, ivec2(slot % SEGMENT_ROW, slot / SEGMENT_ROW), 0).rg + 0.5);
  int point = start.x + (start.y << 16) + ((slot_vertex >> 1) & 1);
  vec4 t0 = point_texel(point, 0), t1 = point_texel(point, 1), t2 = point_texel(point, 2), t3 = point_texel(point, 3);
  thick_vertex(t0.xyz, vec3(t0.w, t1.xy), vec3(t1.zw, t2.x), t2.yzw, t3.xy, t3.zw, (slot_vertex & 1) == 0 ? -1.0 : 1.0,
               uint(point) / uint(frame.counts.y));
}
#else
void main()
{
  thick_vertex(position, tangent, major, minor, cluster, select_key, (gl_VertexID & 1) == 0 ? -1.0 : 1.0,
               uint(gl_VertexID) / (2u * uint(frame.counts.y)));
}
#endif
