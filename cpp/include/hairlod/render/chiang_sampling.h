#pragma once
// Importance sampling of the near-field Chiang BCSDF (Chiang et al. 2016, Sec. 4.2; d'Eon et al.
// 2011): a lobe p chosen with probability proportional to A_p, theta_i from the rough-cone lobe M_p,
// phi_i from the deflection Phi(p, h) plus a trimmed logistic (N_p), uniform for TRRT+.
#include <array>

#include <glm/vec3.hpp>

#include "hairlod/bcsdf/chiang.h"

namespace hairlod::render {

struct BcsdfSample {
    glm::dvec3 wi{0.0};
    glm::dvec3 value{0.0};  // S(wi, wo) cos(theta_i) (RGB), the integrand of the BCSDF measure (docs/ARCHITECTURE.md)
    double pdf = 0.0;       // per unit solid angle
};

// Probability of each lobe R, TT, TRT, TRRT+ at the outgoing inclination (sin, cos) and offset h:
// channel-mean A_p times the lobe weight, normalised (uniform if all vanish).
std::array<double, 4> chiang_lobe_probabilities(const bcsdf::ChiangBcsdf& bcsdf, double sin_theta_o,
                                                double cos_theta_o, double h);

// Samples wi for wo (fibre frame, tangent +x) at offset h in [-1, 1] from four uniforms in [0, 1).
BcsdfSample sample_chiang(const bcsdf::ChiangBcsdf& bcsdf, const glm::dvec3& wo, double h,
                          const std::array<double, 4>& u);

// The solid-angle density with which sample_chiang returns wi.
double chiang_pdf(const bcsdf::ChiangBcsdf& bcsdf, const glm::dvec3& wi, const glm::dvec3& wo, double h);

// A far-field proposal: sample_chiang at one of kFarFieldOffsets offsets h_k = -1 + (2k + 1) / K,
// chosen with u[4]. At one h a smooth fibre's azimuthal lobes are narrow; a far-field BCSDF (the
// aggregated one, integrated over h) spreads over phi, and a one-h proposal misses most of it.
inline constexpr int kFarFieldOffsets = 8;
BcsdfSample sample_chiang_far_field(const bcsdf::ChiangBcsdf& bcsdf, const glm::dvec3& wo, const std::array<double, 5>& u);

// Its density: the mean of chiang_pdf over the K offsets. The returned sample's value is the
// near-field S at the chosen offset; callers of a far-field model evaluate their own.
double chiang_far_field_pdf(const bcsdf::ChiangBcsdf& bcsdf, const glm::dvec3& wi, const glm::dvec3& wo);

}  // namespace hairlod::render
