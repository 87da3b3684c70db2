#pragma once
// The energy-conserving hair model of d'Eon et al. 2011 / Chiang et al. 2016 (the one Cycles uses):
// lobes R, TT, TRT and the residual TRRT+, S = sum_p M_p A_p N_p / cos(theta_i).
#include <span>
#include <vector>

#include "hairlod/bcsdf/bcsdf.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/fiber_rtd.h"

namespace hairlod::bcsdf {

class ChiangBcsdf final : public FiberBcsdf {
public:
    explicit ChiangBcsdf(const HairParams& params);

    // Far field: N_p averaged over the offset h in [-1, 1] (d'Eon et al. 2011, Sec. 4), integrated with
    // composite Gauss-Legendre in gamma_o = asin(h), panels of width 3s, between 8 and 512 panels:
    // within 1e-4 of adaptive quadrature for beta_n >= 0.1 (tested); below beta_n ~ 0.02 the cap
    // leaves the narrow logistic under-resolved (finite, less accurate). Costs ~8 x panels fibre paths.
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    // The far field's azimuthal part for light leaving at inclination theta_o (sin, cos) and azimuth phi
    // between the projections: N_p = 1/2 integral over h of A_p(h) D(phi - Phi(p, h)) dh for R, TT, TRT,
    // and A_3 / (2 pi) for the uniform TRRT+, without the lobe weights; eval_lobes(wi, wo) is
    // weight_p M_p N_p / cos(theta_i). Even in theta_o and in phi.
    LobeValues far_field_azimuthal(double sin_theta_o, double cos_theta_o, double phi) const;
    // The far field of light that crossed other hairs first (Huang 2025 Eq. 7 and 9, as the aggregated
    // BCSDF widens its fibre's lobes): every M_p's variance grows by spread.longitudinal_variance, every
    // A_p is multiplied by spread.attenuation, and every N_p is convolved with a wrapped Gaussian of
    // variance spread.azimuthal_variance on its first harmonic: N_p -> mean + exp(-variance / 2) (N_p - mean),
    // the mean A_p / (2 pi), which keeps its integral.
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, const RtdSpread& spread) const;
    // Near field at the offset h in [-1, 1] of the outgoing ray, as a path tracer evaluates it.
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, double h) const;
    std::span<const LongitudinalLobe> lobe_shapes() const override { return lobes_; }
    std::string_view name() const override { return "chiang"; }

    // Trimmed logistic of scale s() over [-pi, pi], normalised (Chiang et al. 2016, Sec. 4.2).
    double azimuthal_lobe(double phi) const;
    // The deflection of path p (Marschner et al. 2003; Xu et al. 2011, Eq. 8): Phi(p, h) = 2 p gamma_t - 2 gamma_o + p pi.
    static double deflection(int p, double gamma_o, double gamma_t);

    const HairParams& params() const { return params_; }
    double scale() const { return s_; }
    // Number of Gauss-Legendre panels of the far-field h integral.
    int far_field_panels() const { return panels_; }

private:
    std::array<double, 4> longitudinal(const FiberDirection& di, const FiberDirection& dout) const;

    HairParams params_;
    std::array<LongitudinalLobe, 4> lobes_;
    double s_;
    double logistic_normalisation_;
    int panels_;
};

// far_field_azimuthal times the lobe weights, tabulated for a shader: value[(p * theta_samples + j) *
// phi_samples + k] for lobe p (R, TT, TRT, TRRT+), theta_o = (pi / 2) j / (theta_samples - 1) and
// phi = pi k / (phi_samples - 1) (nodes at both ends; both halves mirror these).
std::vector<glm::dvec3> far_field_azimuthal_table(const ChiangBcsdf& bcsdf, int theta_samples, int phi_samples);

// Near-field batch: out[k] = S(wi[k], wo[k]; h[k]).
void evaluate_near_field(const ChiangBcsdf& bcsdf, std::span<const glm::vec3> wi, std::span<const glm::vec3> wo,
                         std::span<const float> h, std::span<glm::vec3> out);

}  // namespace hairlod::bcsdf
