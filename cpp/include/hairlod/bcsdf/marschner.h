#pragma once
// Marschner et al. 2003 as written in circular-gaussian-hair-env-lighting.txt Sec. 4.1 (Xu et al.
// 2011, Eq. 6-10 and 24): S_t = M_t(theta_h) N_t(eta', theta_d, phi) / cos^2(theta_d), t in R, TT, TRT.
#include <numbers>

#include "hairlod/bcsdf/bcsdf.h"

namespace hairlod::bcsdf {

// Treatment of the TRT caustic (Marschner et al. 2003, Sec. 4.3; parameter ranges of their Table 1).
struct MarschnerCaustic {
    double width = 15.0 * std::numbers::pi / 180.0;  // w_c: standard deviation of the caustic lobes
    double fade_range = 0.3;                          // Delta eta': the window fades over eta' in [2, 2 + it]
    double max_window = 0.5;                          // Delta h_M: largest h-window removed around a caustic
};

// Real roots gamma in [-pi/2, pi/2] of Marschner's cubic (Marschner et al. 2003, Eq. 10 with
// gamma_t ~ 3c/pi gamma - 4c/pi^3 gamma^3, c = asin(1/eta')): phi(p, gamma) = phi (mod 2 pi).
struct AzimuthalRoots {
    std::array<double, 3> gamma{};
    int count = 0;
};
AzimuthalRoots marschner_roots(int p, double phi, double eta_prime);

// d phi / d gamma of the cubic above.
double marschner_dphi_dgamma(int p, double gamma, double eta_prime);

class MarschnerBcsdf final : public FiberBcsdf {
public:
    explicit MarschnerBcsdf(const HairParams& params, const MarschnerCaustic& caustic = {});

    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    std::span<const LongitudinalLobe> lobe_shapes() const override { return lobes_; }
    std::string_view name() const override { return "marschner"; }

    // Xu et al. 2011, Eq. 9-10: N_p(phi) at relative azimuth phi and difference angle theta_d, with
    // index eta (TRT uses eta*(phi_h) of Eq. 24 through eval_lobes); RGB.
    glm::dvec3 azimuthal(int p, double phi, double theta_d, double eta) const;
    // Xu et al. 2011, Eq. 10: A_p at offset h.
    glm::dvec3 attenuation(int p, double h, double theta_d, double eta) const;
    // Eq. 24: eta*(phi_h) for the TRT lobe.
    double eccentric_eta(double phi_h) const;

private:
    glm::dvec3 trt_azimuthal(double phi, double theta_d, double eta) const;

    HairParams params_;
    MarschnerCaustic caustic_;
    std::array<LongitudinalLobe, 3> lobes_;
};

}  // namespace hairlod::bcsdf
