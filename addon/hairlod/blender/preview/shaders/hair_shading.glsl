/* The radiance (scene-linear) a hair sends towards the camera (shading_mode 0; hair.frag.glsl and the
 * strands' deferred shading, hair_layer.py). World space: `position` on the hair's centre line (a strand's
 * line, or a thick hair's strip), `t` its unit tangent, `wo` the unit direction towards the camera;
 * for a thick hair `across` is the offset from its centre line in silhouette half-widths, `ellipse`
 * (r_A, r_B, silhouette half-width w) and `cluster` (its strands N, density rho); a strand has
 * ellipse.z = 0 and cluster = (1, 1).
 * Lights: up to 8 (frame.counts.x of them; `frame` is the HairFrame uniform block, lod_preview.py),
 * light_vectors[k] = (unit direction towards a sun, 0) or (position of a point light, 1);
 * light_colours[k].rgb = the sun's irradiance, or the point light's intensity (its power over 4 pi)
 * that falls off with the squared distance, each times its self-shadowing transmittance through the
 * hair: through the light's deep opacity map (opacity_map.glsl) for the first lights, for the others
 * through the hair volume (self_shadow.glsl: frame.hair_centre.xyz and frame.hair_axes.xyz, the
 * object-space ellipsoid, and frame.hair_centre.w, sigma; 0 disables it). Plus the world, through the hair volume
 * as the lights: as SRBF lights (srbf_world.glsl) when hair_world.uniform_part.w = 1, its uniform part
 * through 14 directions split by side (hair_world_transmittance, world_by_side) and each lobe through the
 * hair on its own way (Xu 2011 Eq. 2), else an ambient term, the world colour times the hair's directional
 * albedo, the fibre's A_R + A_TT + A_D at theta_o (which the SRBF table's uniform row holds too: a uniform
 * world reads the same either way) through the same 14 directions; either with the light the hair around
 * scatters on from the directions it blocks (hair_scattered_share, frame.scattering.rgb its albedo) and
 * attenuated by a_F^(n-1), the light a thick hair's n - 1 forward scatterings pass on (Huang 2025 Eq. 7).
 * The lights are shaded with the material's own fibre (aggregated_bcsdf.glsl). */

/* The uniform world's transmittance as the fibre gathers it at |theta_o| (Chiang et al. 2016's lobes): its
 * R share (A_R of the albedo) from the directions on the camera's side, its TT share from the far side,
 * the rest (TRT and beyond, D of the fibre's albedo) from every direction. */
vec3 world_by_side(float abs_theta_o, vec3 near, vec3 far, vec3 all_directions)
{
  vec3 a_r = lut_row(fiber_lut, 0, abs_theta_o, 0.0, 0.5 * HAIRLOD_PI);
  vec3 a_tt = lut_row(fiber_lut, 1, abs_theta_o, 0.0, 0.5 * HAIRLOD_PI);
  vec3 a_d = lut_row(fiber_lut, 2, abs_theta_o, 0.0, 0.5 * HAIRLOD_PI);
  return (a_r * near + a_tt * far + a_d * all_directions) / max(a_r + a_tt + a_d, vec3(1e-6));
}

vec3 hair_radiance(vec3 position, vec3 t, vec3 wo, float across, vec3 ellipse, vec2 cluster)
{
  float n = 1.0, rho = cluster.y;
  /* Where the hair the camera sees begins: a strand's line, or the near side of a thick hair's ellipse
   * (the strip lies on its centre line), half the view ray's chord nearer. */
  vec3 seen = position;
  if (ellipse.z > 0.0) {
    /* Sec. 4: the view ray's chord through the ellipse at this offset from its centre line;
     * 2 r_A r_B / w through the middle, w the silhouette half-width, longer as the ray tilts along t. */
    float along = sqrt(max(1.0 - dot(wo, t) * dot(wo, t), 0.05 * 0.05));
    float chord = 2.0 * ellipse.x * ellipse.y / max(ellipse.z, 1e-20) * sqrt(max(1.0 - across * across, 0.0)) / along;
    n = min(hairs_crossed(rho, chord, cluster.x, ellipse.x, ellipse.y), lut_constants.y);
    seen += min(0.5 * chord, ellipse.x) * wo;
    if (frame.counts.z > 0.5) {
      /* Drawn by coverage (thick_hair.vert.glsl), the fragment stands for a camera ray that meets a strand
       * of this hair, as the path tracer's thick hairs are shaded at the first strand the ray meets: the
       * strands crossed are Poisson along the chord with mean tau, so that strand lies at the mean depth
       * of an exponential cut at the chord, chord (1 / tau - e^-tau / (1 - e^-tau)) (half the chord in a
       * sparse hair, 1 / density in a dense one). */
      float tau = max(hairs_on_ray(rho, chord, cluster.x, ellipse.x, ellipse.y), 1e-4);
      float span = 2.0 * min(0.5 * chord, ellipse.x);  /* from the near side, as far as it was moved */
      seen -= span * (1.0 / tau - exp(-tau) / max(1.0 - exp(-tau), 1e-8)) * wo;
    }
  }
  vec3 radiance = vec3(0.0);
  vec3 p_object = (frame.model_inverse * vec4(position, 1.0)).xyz;
  /* The world reaches the hair through the hair volume as the lights do (object space, as the volume),
   * at the mean depth where the camera's first strand lies (as visible_transmittance, opacity_map.glsl:
   * the mean free path 1 / sigma into the hair; sigma the density under the first mapped light's lit
   * side, else the volume's). The strands on the way pass a_f of the light on forwards (dual scattering,
   * Zinke et al. 2008): through the volume, a uniform random medium, the mean of a_f^N over the Poisson
   * number N of strands crossed is exp(-tau (1 - a_f)) = T^(1 - a_f) per channel and direction, a_f at
   * the direction's inclination to the strand (forward_share). Strands and thick hairs drawn by their
   * coverage (coverage_choice.glsl) are the hair the camera sees, at its own depth (a thick hair's at
   * the strand the ray meets, above): there the depth is 0. */
  bool at_own_depth = frame.counts.z > 0.5;
  float first_density = frame.light_shadow[0].w > 0.5 && !at_own_depth ? light_side_density(0, seen) : 0.0;
  float visible_density = frame.light_shadow[0].w > 0.5 || at_own_depth ? first_density : frame.hair_centre.w;
  vec3 into_object = (frame.model_inverse * vec4(-wo, 0.0)).xyz;
  float reach = frame.light_shadow[0].w > 0.5 ? OPACITY_LAYER_STEPS.w * frame.light_shadow[0].z
                                              : max(max(frame.hair_axes.x, frame.hair_axes.y), frame.hair_axes.z);
  float world_depth = visible_density > 0.0 ? min(1.0 / visible_density, reach) : 0.0;
  vec3 world_point = (frame.model_inverse * vec4(seen, 1.0)).xyz + world_depth * into_object;
  /* Each direction's strands pass on a_f at that direction's inclination to the hair, as a sun's do
   * (the hair near a strand runs along it): in world space, where t is. */
  vec3 world_keep[14];
  for (int k = 0; k < 14; ++k) {
    world_keep[k] = vec3(1.0) - forward_share(normalize(mat3(frame.model) * HAIR_WORLD_DIRECTIONS[k]), t);
  }
  /* Through the strands' own density where the occlusion grid is bound (world_occlusion.glsl: a head of
   * hair's hollow inside and its tips below as they are, the strands passing the light that runs along
   * them), else through the hair-volume ellipsoid. */
  bool world_grid = frame.world_grid_lower.w > 0.0;
  float world_tau[14], facing[14];
  if (world_grid) {
    world_grid_depths(world_point, frame.world_grid_lower, frame.world_grid_extent.xyz, world_tau);
  }
  else {
    hair_world_depths(world_point, frame.hair_centre.xyz, frame.hair_axes.xyz, frame.hair_centre.w, world_tau);
  }
  /* Over all 14 directions, and over those on the camera's side and the far side apart: a strand on the
   * outside of dense hair takes its R light from the camera's side, through little hair, its TT light from
   * behind, through the hair (world_by_side). */
  for (int k = 0; k < 14; ++k) {
    facing[k] = dot(mat3(frame.model) * HAIR_WORLD_DIRECTIONS[k], wo);
  }
  vec3 world_near, world_far;
  vec3 world_shadow = hair_world_transmittance(world_tau, world_keep, facing, world_near, world_far);
  vec3 world_sides = world_by_side(abs(asin(clamp(dot(wo, t), -1.0, 1.0))), world_near, world_far, world_shadow);
  for (int k = 0; k < int(frame.counts.x); ++k) {
    vec3 to_light = frame.light_vectors[k].xyz - position * frame.light_vectors[k].w;
    /* Self-shadowing in object space, where the hair volume is: w = 1 maps a position, w = 0 a direction. */
    vec3 to_light_object = (frame.model_inverse * frame.light_vectors[k]).xyz - p_object * frame.light_vectors[k].w;
    float distance2 = frame.light_vectors[k].w > 0.0 ? max(dot(to_light, to_light), 1e-20) : 1.0;
    vec3 wi = normalize(to_light);
    float sin_i = dot(wi, t);
    float cos_i = sqrt(max(1.0 - sin_i * sin_i, 0.0));
    /* The strands on the light's way pass a_f of it on forwards, coloured (dual scattering, Zinke et al.
     * 2008 Sec. 4.2; a_f at the light's inclination). */
    vec3 a_f = forward_share(wi, t);
    vec3 shadow;
    float straight = 1.0;
    /* The back-scatter of the hair behind (B^'s A_1 + A_3) needs hair there: the chance that the light
     * passing the hair meets a strand beyond it, 1 - exp(-tau) over the map's optical depth past the
     * hair; a sparse wisp has little behind it. Lights without a map keep it whole. */
    float behind = 1.0;
    if (k < OPACITY_MAX_LIGHTS && frame.light_shadow[k].w > 0.5) {
      behind = 1.0 - exp(-hair_behind_optical_depth(k, seen));
      /* The light's deep opacity map (opacity_map.glsl), over the depths where the camera's first strand
       * lies, read a pixel nearer the light than each (past the hair's own sample). The map counts the
       * strands themselves: the light that crossed tau of them keeps Zinke's forward transmittance
       * T_f = prod a_f = a_f^tau = exp(-tau (-ln a_f)) per sample, the spread of tau between the samples
       * (depths, texels) averaged after. */
      shadow = visible_transmittance_straight(k, seen, -wo, k == 0 || at_own_depth ? first_density : light_side_density(k, seen),
                                              light_pixel_size(k, light_depth(k, seen)), -frame.shadow.z * log(a_f),
                                              OPACITY_LAYER_STEPS.w * frame.light_shadow[k].z, frame.shadow.z, straight);
    }
    else {
      /* Through the hair volume, a uniform random medium (self_shadow.glsl): the number of strands crossed
       * is Poisson with mean tau, and the mean of a_f^N over it is exp(-tau (1 - a_f)) = T^(1 - a_f). */
      shadow = exp(-(vec3(1.0) - a_f) * hair_optical_depth(p_object, to_light_object, frame.light_vectors[k].w > 0.0 ? 1.0 : 1e30,
                                                            frame.hair_centre.xyz, frame.hair_axes.xyz, frame.hair_centre.w));
    }
    /* Light that crossed strands on its way arrives widened by their forward scatterings (Zinke et al. 2008
     * Sec. 4.2's global multiple scattering, as Huang 2025 Eq. 9 widens a thick hair's lobes): of the
     * transmitted light, the share exp(-tau) crossed none; the rest crossed, on average, N of them, the Poisson
     * number of strands crossed weighted by the a_f^N each keeps, given N >= 1: tau a_f / (1 - exp(-tau a_f)). */
    vec3 incoming = frame.light_colours[k].rgb / distance2 * cos_i;
    vec3 passed = max(shadow - vec3(straight), vec3(0.0));
    float tau = -log(max(straight, 1e-6)) / max(frame.shadow.z, 1e-6);
    float kept = frame.shadow.z * tau * (a_f.r + a_f.g + a_f.b) / 3.0;
    float crossed = kept > 1e-4 ? kept / (1.0 - exp(-kept)) : 1.0;
    radiance += incoming * (min(vec3(straight), shadow) * aggregated_bcsdf_behind(wi, wo, t, n, rho, behind) +
                            passed * aggregated_bcsdf_crossed(wi, wo, t, n, rho, behind, crossed));
  }
  if (hair_world.uniform_part.w > 0.5) {
    /* Each SRBF light reaches the hair through the hair on its own way (Xu 2011 Eq. 2, the effective
     * transmittance T~(w_j) of light j): a lobe behind the hair lights it through all of it, a lobe on
     * the camera's side through the little in front. Through the hair volume as the suns without a
     * map, the strands on the way passing a_f of it on forwards (T^(1 - a_f)); the uniform part through
     * the 14 directions above. */
    float sin_o = clamp(dot(wo, t), -1.0, 1.0);
    float node_o = srbf_theta_node(sin_o);
    vec3 po = wo - sin_o * t;
    /* The response to a uniform unit world, for the uniform part and for the light scattered on below. */
    vec3 uniform_response = srbf_uniform_response(node_o);
    vec3 world = hair_world.uniform_part.rgb * uniform_response * world_sides;
    /* The world's light that reaches p straight, averaged over the sphere: a lobe's mean radiance is
     * L_j (1 - e^(-2 kappa)) / (2 kappa) (lobe_colours[j].w, world_srbf.py), times its transmittance. */
    vec3 reaching = hair_world.uniform_part.rgb * world_shadow;
    for (int k = 0; k < int(hair_world.counts.x); ++k) {
      vec3 towards_object = (frame.model_inverse * vec4(hair_world.lobe_directions[k].xyz, 0.0)).xyz;
      vec3 lobe_keep = vec3(1.0) - forward_share(normalize(hair_world.lobe_directions[k].xyz), t);
      /* Through the ellipsoid's chord towards the lobe's centre, also where the grid is bound: the grid's
       * 14 directions blended by the lobe (Xu 2011 Eq. 2 over them) took the mohawk under courtyard.exr
       * from 0.90 / 0.90 / 0.91 of the path tracer's radiance to 0.85 / 0.83 / 0.82, the generated hair from
       * 1.01 / 1.03 / 0.95 to 1.17 / 1.11 / 0.85 (docs/preview.md). */
      vec3 through = exp(-lobe_keep * hair_optical_depth(world_point, towards_object, 1e30, frame.hair_centre.xyz,
                                                          frame.hair_axes.xyz, frame.hair_centre.w));
      world += hair_world.lobe_colours[k].rgb * srbf_lobe_response(k, t, node_o, po) * through;
      reaching += hair_world.lobe_colours[k].rgb * hair_world.lobe_colours[k].w * through;
    }
    /* The hair around p scatters the world's light on to it from the directions it blocks, as from a
     * uniform world (hair_scattered_share, self_shadow.glsl): the response to a uniform unit world times
     * that light. */
    world += uniform_response * reaching * hair_scattered_share(world_shadow, frame.scattering.rgb);
    radiance += world * forward_attenuation(0.0, n);
  }
  else {
    float theta_o = abs(asin(clamp(dot(wo, t), -1.0, 1.0)));
    vec3 albedo = lut_row(fiber_lut, 0, theta_o, 0.0, 0.5 * HAIRLOD_PI) + lut_row(fiber_lut, 1, theta_o, 0.0, 0.5 * HAIRLOD_PI) +
                  lut_row(fiber_lut, 2, theta_o, 0.0, 0.5 * HAIRLOD_PI);
    /* With what the hair around p scatters on to it (hair_scattered_share): T / (1 - rho (1 - T)) of it. */
    radiance += frame.ambient.rgb * albedo * forward_attenuation(0.0, n) *
                (world_sides + world_shadow * hair_scattered_share(world_shadow, frame.scattering.rgb));
  }
  return radiance;
}
