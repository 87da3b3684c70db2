/* Self-shadowing by exponential falloff through the hair volume (realtime-pbr-hair-thesis.txt
 * Sec. 4.5, after Karis 2016), without a shadow map: the depth below the lit side is the length of
 * the path from p towards the light inside the hair's bounding ellipsoid (centre, semi_axes), and
 * the light that reaches p is exp(-sigma depth) (hair_optical_depth is sigma depth). Object space; to_light is the direction towards a
 * sun (t_max huge) or the vector to a point light (t_max = 1, the path ends at the light).
 * hairlod/self_shadow.py is the reference (same formula, float64). */
float hair_optical_depth(vec3 p, vec3 to_light, float t_max, vec3 centre, vec3 semi_axes, float sigma)
{
  /* The ray in the ellipsoid's unit-sphere coordinates: |q + t v|^2 = 1. */
  vec3 q = (p - centre) / semi_axes;
  vec3 v = to_light / semi_axes;
  float a = dot(v, v);
  float b = dot(q, v);
  float discriminant = b * b - a * (dot(q, q) - 1.0);
  if (sigma <= 0.0 || a <= 1e-30 || discriminant <= 0.0) {
    return 0.0;
  }
  float root = sqrt(discriminant);
  float t_enter = max((-b - root) / a, 0.0);
  float t_exit = min((-b + root) / a, t_max);
  return sigma * max(t_exit - t_enter, 0.0) * length(to_light);
}

float hair_transmittance(vec3 p, vec3 to_light, float t_max, vec3 centre, vec3 semi_axes, float sigma)
{
  return exp(-hair_optical_depth(p, to_light, t_max, centre, semi_axes, sigma));
}

/* Unit directions a uniform world's light is averaged over, in the order of hairlod/self_shadow.py's
 * WORLD_DIRECTIONS (a keep per direction follows it): +x, +y, +z, -x, -y, -z, then the 8 diagonals
 * (+-1, +-1, +-1) / sqrt(3), x slowest. */
const float HAIR_WORLD_DIAGONAL = 0.57735026919;
const vec3 HAIR_WORLD_DIRECTIONS[14] = vec3[](
    vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(-1, 0, 0), vec3(0, -1, 0), vec3(0, 0, -1),
    vec3(HAIR_WORLD_DIAGONAL, HAIR_WORLD_DIAGONAL, HAIR_WORLD_DIAGONAL),
    vec3(HAIR_WORLD_DIAGONAL, HAIR_WORLD_DIAGONAL, -HAIR_WORLD_DIAGONAL),
    vec3(HAIR_WORLD_DIAGONAL, -HAIR_WORLD_DIAGONAL, HAIR_WORLD_DIAGONAL),
    vec3(HAIR_WORLD_DIAGONAL, -HAIR_WORLD_DIAGONAL, -HAIR_WORLD_DIAGONAL),
    vec3(-HAIR_WORLD_DIAGONAL, HAIR_WORLD_DIAGONAL, HAIR_WORLD_DIAGONAL),
    vec3(-HAIR_WORLD_DIAGONAL, HAIR_WORLD_DIAGONAL, -HAIR_WORLD_DIAGONAL),
    vec3(-HAIR_WORLD_DIAGONAL, -HAIR_WORLD_DIAGONAL, HAIR_WORLD_DIAGONAL),
    vec3(-HAIR_WORLD_DIAGONAL, -HAIR_WORLD_DIAGONAL, -HAIR_WORLD_DIAGONAL));

/* The optical depths from p out to the world along HAIR_WORLD_DIRECTIONS through the hair volume
 * (object space): hair_optical_depth towards each direction taken as a sun. */
void hair_world_depths(vec3 p, vec3 centre, vec3 semi_axes, float sigma, out float tau[14])
{
  for (int k = 0; k < 14; ++k) {
    tau[k] = hair_optical_depth(p, HAIR_WORLD_DIRECTIONS[k], 1e30, centre, semi_axes, sigma);
  }
}

/* The share of a uniform world's light that reaches a point through the hair, per channel, from its
 * optical depths tau along HAIR_WORLD_DIRECTIONS (hair_world_depths, or the grid's world_grid_depths): each
 * direction's T raised to its own keep[k] (1 - a_f at that direction's inclination to the strand: the
 * strands on the way pass a_f of the light on forwards, as they do a sun's), exp(-keep tau), averaged
 * over the 14 directions (returned), and over the directions on the camera's side (facing[k] > 0, the
 * cosine between direction k and the direction towards the camera) and on the far side apart (`near`,
 * `far`), a direction across the view counting half to each. Averaging T first and raising the mean
 * overstates the light wherever the directions differ (Jensen's inequality), most in the channels hair
 * scatters forwards most, red for brown hair. hairlod/self_shadow.py's world_transmittance_by_side is the
 * reference. */
vec3 hair_world_transmittance(float tau[14], vec3 keep[14], float facing[14], out vec3 near, out vec3 far)
{
  near = vec3(0.0);
  far = vec3(0.0);
  float near_count = 0.0;
  for (int k = 0; k < 14; ++k) {
    vec3 through = exp(-keep[k] * tau[k]);
    float near_weight = facing[k] > 1e-4 ? 1.0 : (facing[k] < -1e-4 ? 0.0 : 0.5);
    near += near_weight * through;
    far += (1.0 - near_weight) * through;
    near_count += near_weight;
  }
  vec3 all_directions = (near + far) / 14.0;
  near = near_count > 0.0 ? near / near_count : all_directions;
  far = near_count < 14.0 ? far / (14.0 - near_count) : all_directions;
  return all_directions;
}

/* The world's light the hair around a point scatters on to it, as a share of the light that reaches the
 * point straight from the world (hairlod.self_shadow.scattered_share says why): (1 - T) rho / (1 - rho
 * (1 - T)), T the world's transmittance to the point (hair_world_transmittance, or the grid's), rho the
 * share of the light the strands do not pass on forwards that they scatter (preview_luts.scattering_albedo);
 * per channel. */
vec3 hair_scattered_share(vec3 transmittance, vec3 albedo)
{
  vec3 blocked = vec3(1.0) - clamp(transmittance, 0.0, 1.0);
  vec3 rho = clamp(albedo, 0.0, 1.0);
  return blocked * rho / max(vec3(1.0) - rho * blocked, vec3(1e-4));
}
