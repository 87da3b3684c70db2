/* Deep opacity maps of the hair (Yuksel and Keyser 2008; hairlod/opacity_map.py has the same formulas
 * and says why). Light k < frame.shadow.y has a map: a tile of OPACITY_TILE pixels at x offset
 * k OPACITY_TILE in depth_map (the depth z0 of the first hair the light meets, 1e30 where none) and
 * opacity_map (the optical depth accumulated by the hairs above z0 + OPACITY_LAYER_STEPS s; s =
 * frame.light_shadow[k].z). frame.light_view_projection[k] is the light's view; light_shadow[k].x the
 * world size of a pixel (per unit distance for a point light, .y = 1). */

/* Depth from light k: along a sun's direction, or the distance to a point light. */
float light_depth(int k, vec3 p)
{
  vec4 light = frame.light_vectors[k];
  return light.w > 0.0 ? length(p - light.xyz) : -dot(light.xyz, p);
}

float light_pixel_size(int k, float depth)
{
  vec4 shadow = frame.light_shadow[k];
  return shadow.y > 0.5 ? shadow.x * depth : shadow.x;
}

#ifndef OPACITY_PASS /* the shading pass reads the maps */
/* tau at `below` under the first hair: piecewise linear through (0, 0) and (OPACITY_LAYER_STEPS s;
 * layers), constant beyond the last layer. Summed segment by segment, each segment's slope times the
 * part of it above `below`, without branches: a software GPU runs every branch a block of fragments
 * takes, and the 4 depths of visible_transmittance fall in different segments. */
float layered_optical_depth(vec4 layers, float below, float spacing)
{
  vec4 starts = vec4(0.0, OPACITY_LAYER_STEPS.xyz);
  vec4 lengths = OPACITY_LAYER_STEPS - starts;
  vec4 slopes = (layers - vec4(0.0, layers.xyz)) / lengths;
  return dot(slopes, clamp(vec4(below / spacing) - starts, vec4(0.0), lengths));
}

/* tau of the hair deeper than `below` (hairlod.opacity_map.optical_depth_behind). */
float optical_depth_behind(vec4 layers, float below, float spacing)
{
  return max(layers.w - layered_optical_depth(layers, below, spacing), 0.0);
}

/* The map's texel under clip-space position `clip` of light k, moved by `offset` texels; (-1, -1) outside
 * the map. */
ivec2 opacity_texel(int k, vec4 clip, vec2 offset)
{
  if (clip.w <= 0.0) {
    return ivec2(-1);
  }
  vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
    return ivec2(-1);
  }
  return clamp(ivec2(floor(uv * float(OPACITY_TILE) + offset)), ivec2(0), ivec2(OPACITY_TILE - 1)) +
         ivec2(k * OPACITY_TILE, 0);
}

/* The hair density under the lit side at p: optical depth per unit depth along the light over the
 * first two layers, at p's texel (0 outside the map or where the light meets no hair). */
float light_side_density(int k, vec3 p)
{
  ivec2 texel = opacity_texel(k, frame.light_view_projection[k] * vec4(p, 1.0), vec2(0.0));
  if (texel.x < 0 || texelFetch(depth_map, texel, 0).r >= 1e29) {
    return 0.0;
  }
  return texelFetch(opacity_map, texel, 0).y / (OPACITY_LAYER_STEPS.y * frame.light_shadow[k].z);
}

/* The optical depth of the hair beyond p along light k's direction (the map's last layer less the depth
 * at p), 0 outside the map. */
float hair_behind_optical_depth(int k, vec3 p)
{
  ivec2 texel = opacity_texel(k, frame.light_view_projection[k] * vec4(p, 1.0), vec2(0.0));
  float first = texel.x < 0 ? 1e30 : texelFetch(depth_map, texel, 0).r;
  if (first >= 1e29) {
    return 0.0;
  }
  return optical_depth_behind(texelFetch(opacity_map, texel, 0), light_depth(k, p) - first, frame.light_shadow[k].z);
}

/* The light of light k reaching the hair a camera sees at p, per channel: exp(-tau keep), keep = -ln a_f
 * scaled by the Shadowing strength (a_f the share of the light each strand crossed passes on forwards:
 * a_f^tau, hair.frag.glsl), tau read `bias` nearer the light. Strands drawn without their coverage and thick hairs
 * are at least a pixel wide, so the first one drawn is the outermost; the strand a camera really sees
 * first lies deeper, where its line
 * of sight has crossed an optical depth of about 1 of the hair in front (the free path in a medium of
 * density sigma is exponential with mean 1 / sigma). The transmittance is averaged over 4 stratified
 * depths t = -ln(1 - u) / sigma along `into` (away from the camera), sigma the density under the lit side
 * at p (`density`, light_side_density), each at most `reach` deep and read from one of the 2 x 2 texels
 * around its position (percentage-closer filtering, as the thesis's shadow maps,
 * realtime-pbr-hair-thesis.txt Sec. 4.5, one texel per depth), those where the light meets no hair left
 * out. 1 outside the map. */
vec3 visible_transmittance_straight(int k, vec3 p, vec3 into, float density, float bias, vec3 keep, float reach,
                                    float per_strand, out float straight)
{
  /* Positions along p + t into are linear in clip space; so is their depth from a sun. */
  vec4 clip = frame.light_view_projection[k] * vec4(p, 1.0);
  vec4 clip_into = frame.light_view_projection[k] * vec4(into, 0.0);
  vec4 light = frame.light_vectors[k];
  vec3 sum = vec3(0.0);
  straight = 0.0;
  int in_hair = 0;
  for (int i = 0; i < 4; ++i) {
    float u = (float(i) + 0.5) / 4.0;
    float t = density > 0.0 ? min(-log(1.0 - u) / density, reach) : 0.0;
    ivec2 texel = opacity_texel(k, clip + t * clip_into, vec2(float(i & 1), float(i >> 1)) - 0.5);
    float first = texel.x < 0 ? 1e30 : texelFetch(depth_map, texel, 0).r;
    if (first >= 1e29) {
      continue;
    }
    vec3 q = p + t * into;
    float depth = light.w > 0.0 ? length(q - light.xyz) : -dot(light.xyz, q);
    float tau = layered_optical_depth(texelFetch(opacity_map, texel, 0), depth - bias - first, frame.light_shadow[k].z);
    sum += exp(-tau * keep);
    straight += exp(-tau * per_strand);
    ++in_hair;
  }
  straight = in_hair > 0 ? straight / float(in_hair) : 1.0;
  /* Texels the light meets no hair in lie beyond the hair's edge (the point is on a strand): they would
   * light an edge strand as if nothing stood above it. 1 where no texel holds hair. */
  return in_hair > 0 ? sum / float(in_hair) : vec3(1.0);
}

vec3 visible_transmittance(int k, vec3 p, vec3 into, float density, float bias, vec3 keep, float reach)
{
  float straight;
  return visible_transmittance_straight(k, p, into, density, bias, keep, reach, 0.0, straight);
}
#endif
