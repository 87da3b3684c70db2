#pragma once
// Isotropic GGX (Trowbridge-Reitz) microfacets on a dielectric interface, as the microfacet hair
// fibre of Huang et al. 2022 uses them: the distribution, Smith's height-correlated shadowing,
// sampling of the visible normals (Heitz 2018), refraction, and the energy a rough dielectric keeps
// in one scattering event (its directional albedo), tabulated for the fibre's energy compensation.
// Vectors are in any frame; `m` is the (meso)normal the microfacets are distributed around.
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

namespace hairlod::bcsdf {

// D(m . h) of GGX with roughness `alpha` (alpha^2 = a2): a2 / (pi ((a2 - 1) c^2 + 1)^2), 0 for c <= 0.
double ggx_distribution(double a2, double cos_mh);

// Smith's Lambda of GGX at a direction making cos `cos_m` with the normal: (sqrt(1 + a2 tan^2) - 1) / 2.
double ggx_lambda(double a2, double cos_m);

// Height-correlated masking-shadowing G2 = 1 / (1 + Lambda_i + Lambda_o).
double ggx_shadowing(double a2, double cos_mi, double cos_mo);

// G2 / G1(i) = (1 + Lambda_i) / (1 + Lambda_i + Lambda_o): the shadowing left once the normals are
// drawn from the distribution visible from i.
double ggx_shadowing_given_visible(double a2, double cos_mi, double cos_mo);

// A microfacet normal h drawn from GGX's distribution of normals visible from `wi` around the unit
// normal `m` (Heitz 2018, "Sampling the GGX Distribution of Visible Normals"), from u1, u2 in [0, 1).
glm::dvec3 sample_ggx_visible_normal(double alpha, const glm::dvec3& wi, const glm::dvec3& m, double u1, double u2);

// Unpolarised Fresnel reflectance of light arriving at cos_i (> 0) on an interface of relative
// index eta (transmitted side over incident side, so eta < 1 from inside); 1 on total internal
// reflection. cos_t receives the cosine of the transmitted direction (0 on total internal reflection).
double fresnel_dielectric_general(double cos_i, double eta, double& cos_t);

// The direction of travel of light that arrives along -wi (wi points away from the interface) and
// refracts through the microfacet h (wi . h = cos_i > 0) into the medium of relative index eta;
// cos_t as fresnel_dielectric_general returns it.
glm::dvec3 refract_direction(const glm::dvec3& wi, const glm::dvec3& h, double cos_i, double cos_t, double eta);

// Directional albedo of a rough GGX dielectric interface, reflection plus transmission, single
// scattering: E = E_h~D_wi[F G2/G1 (reflected) + (1 - F) G2/G1 (transmitted)], for light arriving at
// cos_i with roughness alpha and relative index eta (either side). Integrated over `samples` x
// `samples` stratified visible normals.
double ggx_dielectric_albedo(double alpha, double cos_i, double eta, int samples = 32);

// Huang et al. 2022 scale each microfacet interaction of the fibre by 1 / E (E: ggx_dielectric_albedo),
// so that a rough interface loses no energy to the single-scattering approximation. This holds 1 / E
// for one roughness and relative index on both sides of the interface, tabulated over the incident
// cosine (64 nodes uniform in sqrt(cos_i), linear between them; each node integrated over 192 x 192
// visible normals; within 1e-3 of E for cos_i >= 0.013). Instances of the same (alpha, eta) share
// their table, made once per process (0.2-0.4 s on 2 cores).
class DielectricEnergyScale {
public:
    // alpha: GGX roughness; eta: the relative index seen from outside (> 0, != 1 allowed either way).
    DielectricEnergyScale(double alpha, double eta);
    // 1 / E for light arriving at cos_i from outside (relative index eta) or, with inside, from inside
    // (1 / eta).
    double operator()(double cos_i, bool inside) const;

private:
    std::shared_ptr<const std::vector<double>> table_;  // outside nodes, then inside nodes
};

}  // namespace hairlod::bcsdf
