#pragma once
// The R, TT, D single fibre of hair-lod-aggregated-bcsdf.txt (Huang et al. 2025, Eq. 1, with the
// lobe shapes of Huang 2025 Eq. 8 at n = 1): S = sum_p A_p M_p(theta_h) N_p(phi), p in {R, TT, D}.
//
// Choices the paper leaves open: A_R, A_TT and A_D are the fibre's attenuations averaged over the
// offset h at theta_o (theta_d on the specular cone; D gathers TRT and every higher order), so that
// the fibre follows HairParams; they are tabulated over |theta_o| at construction (257 samples, linear
// interpolation, 1e-5); the Gaussians G(beta, x) have variance beta (as Huang 2025 Eq. 9 adds variances);
// M_p is the rough-cone form of G (d'Eon et al. 2011), unit-area under cos(theta_i) dtheta_i, and
// S carries 1/cos(theta_i), so the lossless fibre conserves energy at every theta_o (white furnace
// within 1e-3) at the price of reciprocity in theta, as in Chiang et al. 2016; the diffuse lobe is normalised to unit energy under the measure cos^2(theta_i) dtheta_i dphi_i
// of Sec. 3 (M_D N_D = 1/pi^2, where Huang 2025 Eq. 8 prints M_D = 1/pi, N_D = 1/(2 pi)).
#include <vector>

#include "hairlod/bcsdf/bcsdf.h"

namespace hairlod::bcsdf {

// Extra spread and attenuation of light that crossed other hairs first (hair-lod-aggregated-bcsdf.txt
// Huang 2025 Eq. 7 and 9): added to the lobes' variances (theta_i measure / azimuth) and multiplying A_p.
struct RtdSpread {
    double longitudinal_variance = 0.0;
    double azimuthal_variance = 0.0;
    glm::dvec3 attenuation{1.0};
};

class FiberRtdBcsdf final : public FiberBcsdf {
public:
    explicit FiberRtdBcsdf(const HairParams& params);

    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, const RtdSpread& spread) const;
    // A_R, A_TT, A_D at inclination theta (lobe weights applied).
    std::array<glm::dvec3, 3> lobe_attenuation(double theta) const;
    std::span<const LongitudinalLobe> lobe_shapes() const override { return lobes_; }
    std::string_view name() const override { return "fiber_rtd"; }

    // Variance of N_TT around phi = pi (Huang 2025 Eq. 8's beta_TT^N, which the paper leaves open): that
    // of the material's own far-field TT lobe (Chiang et al. 2016, averaged over the offset h) at normal
    // incidence, at least its logistic's pi^2 s^2 / 3.
    double azimuthal_variance() const { return azimuthal_variance_; }

private:
    HairParams params_;
    std::array<LongitudinalLobe, 3> lobes_;  // R, TT, D (D: uniform, variance pi^2 / 12)
    double azimuthal_variance_;
    std::vector<std::array<glm::dvec3, 3>> attenuation_table_;  // over |theta_d| in [0, pi/2]
};

}  // namespace hairlod::bcsdf
