/* The world as SRBF lights (Xu et al. 2011, circular-gaussian-hair-env-lighting.txt, Sec. 3, Eq. 2):
 * radiance towards wo from a hair of unit tangent t under c_0 + sum_j L_j G(w; w_j, lambda), world
 * space. Each lobe's single scattering (Xu 2011 Eq. 2, the integral of G S cos(theta_i) over the sphere for the
 * R / TT / D fibre, hairlod.preview_luts.lobe_responses) is read from srbf_lut (hairlod.preview_luts.srbf_tables,
 * read the same way by preview_luts.srbf_lookup): it depends only on theta_o,
 * theta_j and |phi_o - phi_j|, trilinear over the table's nodes (theta nodes pi/2 sin(pi s / 2), s
 * uniform in [-1, 1]; phi nodes uniform in [0, pi]); the last row is the response to a uniform world,
 * the material's own directional albedo (hairlod.preview_luts.uniform_world_response).
 * Needs: sampler2D srbf_lut; the HairWorld block `hair_world` (world_srbf.py): hair_world.uniform_part.rgb = c_0,
 * hair_world.counts.x = the lobe count, hair_world.lobe_directions[j].xyz = w_j, hair_world.lobe_colours[j].rgb = L_j;
 * lut_row from aggregated_bcsdf.glsl. */

/* theta in node units of srbf_lut: the inverse of preview_luts.theta_nodes. */
float srbf_theta_node(float sin_theta)
{
  float s = asin(clamp(asin(clamp(sin_theta, -1.0, 1.0)) / (0.5 * HAIRLOD_PI), -1.0, 1.0)) / (0.5 * HAIRLOD_PI);
  return (0.5 * s + 0.5) * float(textureSize(srbf_lut, 0).x - 1);
}

/* The response to one unit lobe at (theta_o, theta_j) in node units and azimuth difference phi. */
vec3 srbf_response(float node_o, float node_j, float phi)
{
  int samples = textureSize(srbf_lut, 0).x;
  int o = min(int(node_o), samples - 2), j = min(int(node_j), samples - 2);
  float u = node_o - float(o), v = node_j - float(j);
  int row = j * samples + o;
  vec3 low = mix(lut_row(srbf_lut, row, phi, 0.0, HAIRLOD_PI), lut_row(srbf_lut, row + 1, phi, 0.0, HAIRLOD_PI), u);
  vec3 high = mix(lut_row(srbf_lut, row + samples, phi, 0.0, HAIRLOD_PI),
                  lut_row(srbf_lut, row + samples + 1, phi, 0.0, HAIRLOD_PI), u);
  return mix(low, high, v);
}

/* The response to lobe k of the world towards wo of a fibre of tangent t, without its colour: sin_o =
 * dot(wo, t), node_o = srbf_theta_node(sin_o), po = wo - sin_o t. */
vec3 srbf_lobe_response(int k, vec3 t, float node_o, vec3 po)
{
  vec3 wj = hair_world.lobe_directions[k].xyz;
  float sin_j = clamp(dot(wj, t), -1.0, 1.0);
  vec3 pj = wj - sin_j * t;
  /* Along the tangent the azimuth is undefined and the response does not depend on it. */
  float projections = length(po) * length(pj);
  float cos_phi = projections > 1e-12 ? clamp(dot(po, pj) / projections, -1.0, 1.0) : 1.0;
  return srbf_response(node_o, srbf_theta_node(sin_j), acos(cos_phi));
}

/* The response to a uniform unit world at theta_o in node units (srbf_lut's last row): the material's
 * directional albedo. */
vec3 srbf_uniform_response(float node_o)
{
  int samples = textureSize(srbf_lut, 0).x;
  return lut_row(srbf_lut, samples * samples, node_o, 0.0, float(samples - 1));
}

vec3 srbf_world(vec3 wo, vec3 t)
{
  float sin_o = clamp(dot(wo, t), -1.0, 1.0);
  float node_o = srbf_theta_node(sin_o);
  vec3 po = wo - sin_o * t;
  vec3 radiance = hair_world.uniform_part.rgb * srbf_uniform_response(node_o);
  for (int k = 0; k < int(hair_world.counts.x); ++k) {
    radiance += hair_world.lobe_colours[k].rgb * srbf_lobe_response(k, t, node_o, po);
  }
  return radiance;
}
