#pragma once
// HairParams: the physical parameters of one hair fibre shared by every BCSDF model, and the
// per-lobe longitudinal shapes (shift, variance) the models derive from them.
#include <array>
#include <numbers>

#include <glm/vec3.hpp>

namespace hairlod::bcsdf {

// The single-fibre model that shades a strand in the path tracer. Chiang: d'Eon et al. 2011 /
// Chiang et al. 2016 (Cycles 3.x's Principled Hair); Huang: the microfacet fibre of Huang et al.
// 2022 (Blender 4.x's default), see huang.h. Every other model (dual scattering, the aggregated and
// real-time BCSDFs, the bake) works on the Chiang fibre of sigma_a, beta_m, beta_n; for a Huang fibre
// those are the Chiang fibre that stands in for it (chiang_stand_in.h), and the Huang fibre's own
// absorption is huang_sigma_a.
enum class FibreModel { Chiang, Huang };

struct HairParams {
    double eta = 1.55;                                // index of refraction of the cortex
    glm::dvec3 sigma_a{0.245531, 0.52, 1.365};        // absorption per unit fibre radius (RGB)
    double beta_m = 0.3;                              // longitudinal roughness in (0, 1], pbrt convention
    double beta_n = 0.3;                              // azimuthal roughness in (0, 1], pbrt convention
    double alpha = 2.0 * std::numbers::pi / 180.0;    // cuticle tilt (radians), positive as in pbrt/Cycles
    double coat = 0.0;                                // in [0, 1]: R-lobe roughness is (1 - coat) beta_m (Cycles)
    double eccentricity = 1.0;                        // Marschner's a (Xu et al. 2011, Eq. 24); 1 = circular
    double weight_r = 1.0;                            // lobe multipliers (1 = physical)
    double weight_tt = 1.0;
    double weight_trt = 1.0;                          // TRT and every higher-order lobe (TRRT+, D)
    FibreModel fibre = FibreModel::Chiang;
    double microfacet_roughness = 0.3;                // Huang: GGX roughness of the cuticle, in [1e-3, 1]
    double aspect_ratio = 1.0;                        // Huang: minor over major axis in [0.1, 1]
    glm::dvec3 huang_sigma_a{0.245531, 0.52, 1.365};  // Huang: absorption per unit fibre radius (RGB)

    // Throws hairlod::Error naming the first invalid parameter (eta <= 1, negative or NaN absorption,
    // beta outside (0, 1], coat outside [0, 1], eccentricity that makes Xu 2011 Eq. 24's eta* <= 1, ...).
    void validate() const;
};

// Longitudinal roughness of the R lobe: (1 - coat) beta_m, clamped below at 1e-3 as Cycles does.
double primary_roughness(const HairParams& params);

// Chiang et al. 2016, Eq. 7: variance v of the longitudinal lobe from the roughness beta_m.
double longitudinal_variance(double beta_m);

// Chiang et al. 2016, Eq. 8: scale s of the azimuthal logistic lobe from the roughness beta_n.
double logistic_scale(double beta_n);

// One longitudinal lobe: centred on theta_h = shift (so on theta_i = 2 shift - theta_o), with
// variance `variance` in theta_i (standard deviation sqrt(variance) / 2 in theta_h).
struct LongitudinalLobe {
    double shift = 0.0;
    double variance = 0.0;
};

// Chiang et al. 2016 Sec. 4 / Cycles: R {-alpha, v_R}, TT {alpha/2, v/4}, TRT {2 alpha, 4 v},
// TRRT+ {0, 4 v}, with v = Chiang 2016 Eq. 7 of beta_m and v_R = Eq. 7 of primary_roughness().
std::array<LongitudinalLobe, 4> chiang_lobes(const HairParams& params);

// Marschner et al. 2003, Table 1 (realtime-pbr-hair-thesis.txt Table 2.2) with Marschner's tilt
// alpha_M = -alpha: R {-alpha, v_R}, TT {alpha/2, v/4}, TRT {3 alpha/2, 4 v}.
std::array<LongitudinalLobe, 3> marschner_lobes(const HairParams& params);

// Chiang et al. 2016, Eq. 9: absorption giving a fibre assembly of diffuse reflectance `color`
// (each channel in (0, 1]) for the azimuthal roughness beta_n.
glm::dvec3 sigma_a_from_color(const glm::dvec3& color, double beta_n);

// Absorption of eumelanin/pheomelanin concentrations with Cycles' coefficients (sRGB primaries).
glm::dvec3 sigma_a_from_melanin(double eumelanin, double pheomelanin);

}  // namespace hairlod::bcsdf
