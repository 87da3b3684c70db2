/* The aggregated BCSDF of a thick hair (hair-lod-aggregated-bcsdf.txt, Huang et al. 2025, Eq. 6-15)
 * over the material's own fibre (Chiang et al. 2016 in the far field, d'Eon et al. 2011 Sec. 4), as
 * cpp/src/bcsdf/aggregated.cpp evaluates it with AggregatedFibre::Material, reading baked tables
 * (cpp/src/bcsdf/bake.cpp, chiang.cpp's far_field_azimuthal_table) instead of integrating:
 *   fiber_lut:       rows A_R, A_TT, A_D over theta_o in [0, pi/2] (the fibre's directional albedo)
 *   dual_lut:        rows a_f, a_b, A_1, A_3, Delta_b, sigma_b, sigma_f^2, beta_f^2 over theta_d in [-pi/2, pi/2]
 *   aggregated_lut:  blocks a_F^(n-1), A_1+, B^ budget, each over (theta_d in [-pi/2, pi/2], n in [1, n_max])
 *   material_lut:    N_p of R, TT, TRT, TRRT+ over (|theta_o|, phi in [0, pi]) and their means over phi
 *                    (preview_luts.material_fibre_rows)
 * Texel centres sit on the axis nodes; every lookup interpolates linearly with texelFetch, so the
 * result does not depend on the sampler's filter. Directions are unit vectors; the fibre tangent is
 * t, theta is measured from the normal plane (sin theta = dot(w, t)), as in pbrt and docs/ARCHITECTURE.md ("Conventions").
 * Needs: sampler2D fiber_lut, dual_lut, aggregated_lut, material_lut; vec4 lobe_shapes (R shift, R variance,
 * TT shift, TT variance); vec4 lobe_tilts (sin 2s, cos 2s of the R and of the TT shift s); vec4 trt_lobe (sin 2s,
 * cos 2s of the TRT shift, its variance, its deon_log_normalisation); vec4 lut_constants (the R / TT / D
 * fibre's TT azimuthal variance, which the material's fibre does not read, n_max, deon_log_normalisation of
 * the R and of the TT variance).
 * Shaders that draw single strands only (n = 1, rho = 1) define HAIRLOD_SINGLE_HAIR: a_F^(n-1) is then
 * constant and left out, and so is A_1+ (a strand holds no hairs behind itself; aggregated_bcsdf_behind). */

#define HAIRLOD_PI 3.14159265358979
#define HAIRLOD_SIDE_SCATTER 0.6  /* d_1+ of Huang 2025 Eq. 10 */
#define HAIRLOD_MULTIPLE_SHADOWING 0.2  /* c_m of Huang 2025 Eq. 13 */

/* Row `row` of a table whose x axis spans [lo, hi] with texel centres on the nodes. */
vec3 lut_row(sampler2D lut, int row, float x, float lo, float hi)
{
  int samples = textureSize(lut, 0).x;
  float position = clamp((x - lo) / (hi - lo), 0.0, 1.0) * float(samples - 1);
  int k = min(int(position), samples - 2);
  float t = position - float(k);
  return mix(texelFetch(lut, ivec2(k, row), 0).rgb, texelFetch(lut, ivec2(k + 1, row), 0).rgb, t);
}

/* a_f, the share of light a strand passes on forwards (dual scattering, Zinke et al. 2008 Sec. 4.2), for
 * light arriving from the unit direction w at a strand of unit tangent t: dual_lut's a_f row at w's
 * inclination asin(w . t), clamped to [1e-4, 1] (hairlod/preview_luts.py forward_share). */
vec3 forward_share(vec3 w, vec3 t)
{
  return clamp(lut_row(dual_lut, 0, asin(clamp(dot(w, t), -1.0, 1.0)), -0.5 * HAIRLOD_PI, 0.5 * HAIRLOD_PI), 1e-4, 1.0);
}

/* Block `block` of aggregated_lut at (theta_d, n): bilinear within the block. */
vec3 aggregated_lookup(int block, float theta_d, float n)
{
  ivec2 size = textureSize(aggregated_lut, 0);
  int n_samples = size.y / 3;
  float y = clamp((n - 1.0) / max(lut_constants.y - 1.0, 1e-6), 0.0, 1.0) * float(n_samples - 1);
  int j = min(int(y), n_samples - 2);
  float u = y - float(j);
  float x = clamp((theta_d + 0.5 * HAIRLOD_PI) / HAIRLOD_PI, 0.0, 1.0) * float(size.x - 1);
  int k = min(int(x), size.x - 2);
  float t = x - float(k);
  int row = block * n_samples + j;
  vec3 low = mix(texelFetch(aggregated_lut, ivec2(k, row), 0).rgb, texelFetch(aggregated_lut, ivec2(k + 1, row), 0).rgb, t);
  vec3 high = mix(texelFetch(aggregated_lut, ivec2(k, row + 1), 0).rgb,
                  texelFetch(aggregated_lut, ivec2(k + 1, row + 1), 0).rgb, t);
  return mix(low, high, u);
}

/* a_F^(n-1) at theta_d (Huang 2025 Eq. 7): the share of light n - 1 hairs crossed before pass on forwards. */
vec3 forward_attenuation(float theta_d, float n)
{
#ifdef HAIRLOD_SINGLE_HAIR
  return vec3(1.0);
#else
  return aggregated_lookup(0, theta_d, n);
#endif
}

/* log(I_0(x)) from the polynomial fits of Abramowitz & Stegun 9.8.1-9.8.2 (relative error < 2e-7). */
float log_bessel_i0(float x)
{
  x = abs(x);
  if (x < 3.75) {
    float t = (x / 3.75) * (x / 3.75);
    return log(1.0 + t * (3.5156229 + t * (3.0899424 + t * (1.2067492 + t * (0.2659732 + t * (0.0360768 +
                                                                                              t * 0.0045813))))));
  }
  float u = 3.75 / x;
  float scaled = 0.39894228 + u * (0.01328592 + u * (0.00225319 + u * (-0.00157565 + u * (0.00916281 +
                 u * (-0.02057706 + u * (0.02635537 + u * (-0.01647633 + u * 0.00392377)))))));
  return x + log(scaled) - 0.5 * log(x);
}

/* The log of the normalisation of d'Eon et al. 2011's longitudinal lobe of variance v,
 * v (1 - exp(-2 / v)) exp(1 / v) = 2 v sinh(1 / v), taken apart so that narrow lobes (1/v ~ 1e3) do not overflow. */
float deon_log_normalisation(float v)
{
  return log(v) + 1.0 / v + log(max(1.0 - exp(-2.0 / v), 1e-30));
}

/* d'Eon et al. 2011 longitudinal lobe of variance v, tilted by a shift s, tilt = (sin 2s, cos 2s) (Chiang et al. 2016 Sec. 4),
 * in log space so that narrow lobes neither overflow nor lose precision; log_normalisation = deon_log_normalisation(v). */
float tilted_deon_longitudinal(float sin_i, float cos_i, float sin_o, float cos_o, vec2 tilt, float v, float log_normalisation)
{
  float sin_2s = tilt.x, cos_2s = tilt.y;
  float sin_op = sin_o * cos_2s - cos_o * sin_2s;
  float cos_op = abs(cos_o * cos_2s + sin_o * sin_2s);
  float a = sin_i * sin_op / v;
  float b = cos_i * cos_op / v;
  return exp(log_bessel_i0(b) - a - log_normalisation);
}

float hairlod_gaussian(float x, float variance)
{
  return exp(-0.5 * x * x / variance) / sqrt(2.0 * HAIRLOD_PI * variance);
}

/* Lobe `lobe`'s (R, TT, TRT, TRRT+) azimuthal part N_p of the material's fibre at |theta_o| and phi in [0, pi]
 * (material_lut: preview_luts.material_fibre_rows), bilinear between the nodes; `keep` in (0, 1] takes it
 * towards its mean over phi (the row's last texel), as forward scatterings spread it, keeping its integral. */
vec3 material_azimuthal(int lobe, float abs_theta_o, float phi, float keep)
{
  ivec2 size = textureSize(material_lut, 0);
  int phi_samples = size.x - 1, theta_samples = size.y / 4;
  float y = clamp(abs_theta_o / (0.5 * HAIRLOD_PI), 0.0, 1.0) * float(theta_samples - 1);
  int j = min(int(y), theta_samples - 2);
  float v = y - float(j);
  float x = clamp(phi / HAIRLOD_PI, 0.0, 1.0) * float(phi_samples - 1);
  int k = min(int(x), phi_samples - 2);
  float u = x - float(k);
  int row = lobe * theta_samples + j;
  vec3 low = mix(texelFetch(material_lut, ivec2(k, row), 0).rgb, texelFetch(material_lut, ivec2(k + 1, row), 0).rgb, u);
  vec3 high = mix(texelFetch(material_lut, ivec2(k, row + 1), 0).rgb,
                  texelFetch(material_lut, ivec2(k + 1, row + 1), 0).rgb, u);
  vec3 value = mix(low, high, v);
  if (keep < 1.0) {
    vec3 mean = mix(texelFetch(material_lut, ivec2(phi_samples, row), 0).rgb,
                    texelFetch(material_lut, ivec2(phi_samples, row + 1), 0).rgb, v);
    value = mean + keep * (value - mean);
  }
  return value;
}

/* S(wi, wo) of a thick hair with n hairs crossed and density rho (Huang 2025 Eq. 6-15) over the material's
 * fibre; built with HAIRLOD_SINGLE_HAIR, of a strand: the material's fibre and the back-scatter of the hair
 * behind it. `behind` in [0, 1] is the share of the light that
 * meets hair beyond the hair along wi: the back-scatter of the hair behind, A_1 + A_3 of B^ (dual
 * scattering's backscattering attenuation, Zinke et al. 2008 Sec. 4.2, for hair that fills the half-space
 * behind), scales with it; A_1+, the hair's own side scattering (Huang 2025 Eq. 10), does not. `crossed`
 * (>= 0) is the number of strands the light crossed on its way to the hair, each widening the lobes by
 * one forward scattering as the n - 1 inside a thick hair do (Zinke et al. 2008 Sec. 4.2's global
 * multiple scattering); their attenuation is the caller's (the light's transmittance). Returns RGB. */
vec3 aggregated_bcsdf_crossed(vec3 wi, vec3 wo, vec3 t, float n, float rho, float behind, float crossed)
{
  float sin_i = clamp(dot(wi, t), -1.0, 1.0), sin_o = clamp(dot(wo, t), -1.0, 1.0);
  float cos_i = sqrt(max(1.0 - sin_i * sin_i, 0.0)), cos_o = sqrt(max(1.0 - sin_o * sin_o, 0.0));
  float theta_i = atan(sin_i, cos_i), theta_o = atan(sin_o, cos_o);
  float theta_d = 0.5 * (theta_o - theta_i);
  /* |phi|, the azimuth between the projections onto the normal plane (every lobe is even in phi). */
  vec3 pi_ = wi - sin_i * t, po = wo - sin_o * t;
  float projections = length(pi_) * length(po);
  float cos_phi = projections > 1e-12 ? clamp(dot(pi_, po) / projections, -1.0, 1.0) : 1.0;
  float phi = acos(cos_phi);

  vec3 a_f = lut_row(dual_lut, 0, theta_d, -0.5 * HAIRLOD_PI, 0.5 * HAIRLOD_PI);
  /* Huang 2025 Eq. 7 and 9: n - 1 forward scatterings attenuate and widen R^, TT^, D^. */
  vec3 attenuation = forward_attenuation(theta_d, n);
  /* Across the fibre the forward scatterings widen by sigma_f^2 each, along it by Zinke's beta_f^2
   * (aggregated.cpp says why): the n - 1 inside a thick hair and the `crossed` on the light's way. */
  float scatterings = n - 1.0 + crossed;
  float spread = 0.0, along = 0.0;
  float v_r = lobe_shapes.y, v_tt = lobe_shapes.w, v_trt = trt_lobe.z;
  /* Unwidened lobes take their normalisations from uniforms (lut_constants.zw, trt_lobe.w) instead of
   * taking them again in every fragment. */
  float normalisation_r = lut_constants.z, normalisation_tt = lut_constants.w, normalisation_trt = trt_lobe.w;
  if (scatterings > 0.0) {
    vec3 sigma_f2 = lut_row(dual_lut, 6, theta_d, -0.5 * HAIRLOD_PI, 0.5 * HAIRLOD_PI);
    vec3 beta_f2 = lut_row(dual_lut, 7, theta_d, -0.5 * HAIRLOD_PI, 0.5 * HAIRLOD_PI);
    spread = scatterings * (sigma_f2.r + sigma_f2.g + sigma_f2.b) / 3.0;
    along = 4.0 * scatterings * (beta_f2.r + beta_f2.g + beta_f2.b) / 3.0;
    v_r += along;
    v_tt += along;
    v_trt += along;
    normalisation_r = deon_log_normalisation(v_r);
    normalisation_tt = deon_log_normalisation(v_tt);
    normalisation_trt = deon_log_normalisation(v_trt);
  }

  /* The material's fibre (Chiang et al. 2016) in the far field: sum_p M_p N_p / cos(theta_i) over R, TT, TRT and
   * TRRT+, N_p tabulated (material_azimuthal), M_p the tilted d'Eon lobes; TRRT+ takes TRT's variance unshifted. */
  /* Huang 2025 Eq. 9's azimuthal spread of the forward scatterings, a wrapped Gaussian of variance `spread`
   * convolved with each lobe, on the lobes' first harmonic: exp(-spread / 2) of their departure from the mean. */
  float keep = exp(-0.5 * spread);
  float abs_theta_o = abs(theta_o);
  float inv_cos_i = 1.0 / max(cos_i, 1e-6);
  float m_r = tilted_deon_longitudinal(sin_i, cos_i, sin_o, cos_o, lobe_tilts.xy, v_r, normalisation_r);
  float m_tt = tilted_deon_longitudinal(sin_i, cos_i, sin_o, cos_o, lobe_tilts.zw, v_tt, normalisation_tt);
  float m_trt = tilted_deon_longitudinal(sin_i, cos_i, sin_o, cos_o, trt_lobe.xy, v_trt, normalisation_trt);
  float m_rest = tilted_deon_longitudinal(sin_i, cos_i, sin_o, cos_o, vec2(0.0, 1.0), v_trt, normalisation_trt);
  vec3 value = attenuation * inv_cos_i * (m_r * material_azimuthal(0, abs_theta_o, phi, keep) +
                                          m_tt * material_azimuthal(1, abs_theta_o, phi, keep) +
                                          m_trt * material_azimuthal(2, abs_theta_o, phi, keep) +
                                          m_rest * material_azimuthal(3, abs_theta_o, phi, keep));

  vec3 shadowing = vec3(1.0);
  if (phi < 0.5 * HAIRLOD_PI) {
    /* Huang 2025 Eq. 10-11: B^ = A_1+ + A_1 + A_3 (the latter two for the hair behind), capped by the budget
     * 1 - a_F^(n-1) (a_f + a_b) at theta_o. */
#ifdef HAIRLOD_SINGLE_HAIR
    /* A strand has none of its own hairs behind it: Huang 2025 Eq. 10's series runs over the hairs a thick hair holds
     * behind the shaded one (none for one hair, as aggregated.cpp's shaded_inside), and the strands behind a
     * strand are the hair behind, A_1 + A_3 times `behind`. At n = 1 the table's A_1+, d_1+ a_B a_F, counted
     * them a second time: the real mohawk's sun term read 1.40 / 1.37 / 1.34 of the path tracer with it,
     * 1.18 / 1.16 / 1.20 without (docs/preview.md). */
    vec3 a_1_plus = vec3(0.0);
#else
    vec3 a_1_plus = aggregated_lookup(1, theta_d, n);
#endif
    vec3 budget = aggregated_lookup(2, theta_o, n);
    vec3 a_1 = lut_row(dual_lut, 2, theta_d, -0.5 * HAIRLOD_PI, 0.5 * HAIRLOD_PI);
    vec3 a_3 = lut_row(dual_lut, 3, theta_d, -0.5 * HAIRLOD_PI, 0.5 * HAIRLOD_PI);
    vec3 delta_b = lut_row(dual_lut, 4, theta_d, -0.5 * HAIRLOD_PI, 0.5 * HAIRLOD_PI);
    vec3 sigma_b = lut_row(dual_lut, 5, theta_d, -0.5 * HAIRLOD_PI, 0.5 * HAIRLOD_PI);
    vec3 a_b = min(a_1_plus + behind * (a_1 + a_3), budget);
    vec3 m_b;
    for (int c = 0; c < 3; ++c) {
      m_b[c] = hairlod_gaussian(theta_i + theta_o - 2.0 * delta_b[c], max(4.0 * sigma_b[c] * sigma_b[c], 1e-12));
    }
    value += a_b * m_b / HAIRLOD_PI;
    /* Huang 2025 Eq. 12-15: shadowing-masking towards the front. */
    float open = 1.0 - rho;
    float p_m = open * HAIRLOD_MULTIPLE_SHADOWING;
    float p_s = clamp(open * (1.0 - cos_phi), 0.0, 1.0 - p_m);
    shadowing = p_s * a_f + vec3(1.0 - p_m - p_s);
  }
  return value * shadowing;
}

/* The same for light that reaches the hair straight. */
vec3 aggregated_bcsdf_behind(vec3 wi, vec3 wo, vec3 t, float n, float rho, float behind)
{
  return aggregated_bcsdf_crossed(wi, wo, t, n, rho, behind, 0.0);
}

/* The same with hair everywhere behind (the model of cpp/src/bcsdf/aggregated.cpp). */
vec3 aggregated_bcsdf(vec3 wi, vec3 wo, vec3 t, float n, float rho)
{
  return aggregated_bcsdf_behind(wi, wo, t, n, rho, 1.0);
}

/* The mean number of hairs a ray of length `ray_length` through a thick hair crosses
 * (hair-lod-aggregated-bcsdf.txt Sec. 4): rho l sqrt(n_total / (pi r_A r_B)). */
float hairs_on_ray(float rho, float ray_length, float n_total, float r_a, float r_b)
{
  return rho * ray_length * sqrt(n_total / (HAIRLOD_PI * max(r_a * r_b, 1e-30)));
}

/* Hairs crossed by a ray that meets the thick hair (Sec. 4's n): hairs_on_ray, at least 1. */
float hairs_crossed(float rho, float ray_length, float n_total, float r_a, float r_b)
{
  return max(1.0, hairs_on_ray(rho, ray_length, n_total, r_a, r_b));
}
