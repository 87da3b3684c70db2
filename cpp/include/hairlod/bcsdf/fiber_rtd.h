#pragma once
// The R, TT, D single fibre of hair-lod-aggregated-bcsdf.txt (Huang et al. 2025, Eq. 1, with the
// lobe shapes of Eq. 8 at n = 1): S = sum_p A_p M_p(theta_h) N_p(phi), p in {R, TT, D}.
//
// Choices the paper leaves open: A_R, A_TT and A_D are the fibre's attenuations averaged over the
// offset h at theta_d (D gathers TRT and every higher order), so that the fibre follows HairParams;
// the Gaussians G(beta, x) have variance beta (as Eq. 9 adds variances) and M_p is unit-area in
// theta_i; the diffuse lobe is normalised to unit energy under the measure cos^2(theta_i) dtheta_i dphi_i
// of Sec. 3 (M_D N_D = 1/pi^2, where Eq. 8 prints M_D = 1/pi, N_D = 1/(2 pi)).
#include "hairlod/bcsdf/bcsdf.h"

namespace hairlod::bcsdf {

class FiberRtdBcsdf final : public FiberBcsdf {
public:
    explicit FiberRtdBcsdf(const HairParams& params);

    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    std::span<const LongitudinalLobe> lobe_shapes() const override { return lobes_; }
    std::string_view name() const override { return "fiber_rtd"; }

    // Variance of N_TT around phi = pi: the variance pi^2 s^2 / 3 of Chiang's logistic of scale s.
    double azimuthal_variance() const { return azimuthal_variance_; }

private:
    HairParams params_;
    std::array<LongitudinalLobe, 3> lobes_;  // R, TT, D (D: uniform, variance pi^2 / 12)
    double azimuthal_variance_;
};

}  // namespace hairlod::bcsdf
