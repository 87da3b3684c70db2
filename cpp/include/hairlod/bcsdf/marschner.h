#pragma once
// Marschner et al. 2003 as written in circular-gaussian-hair-env-lighting.txt Sec. 4.1
// (Xu et al. 2011, Eq. 6-10 and 24): S_t = M_t(theta_h) N_t(eta', theta_d, phi) / cos^2(theta_d), t in R, TT, TRT.
//
// Decision (energy): as written, the lossless fibre returns more than it receives where
// cos^2(theta_i) / cos^2(theta_d) exceeds 1 over a lobe: 1.12 at theta_o = -1.5 with alpha = 2 deg,
// 1.03 at theta_o = 0.8 with alpha = 10 deg (R and TT lobes see different theta_d), 1.87 at
// |theta_o| = pi/2 - 1e-4 even untilted. The model therefore tabulates its own white furnace E(theta_o)
// (per channel, from the h-averaged attenuations, so a 1D integral per theta_o) at construction and
// divides by max(1, E(theta_o)): unchanged wherever it conserved energy, and reciprocal only there.
#include <numbers>
#include <vector>

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
    // index eta (TRT uses eta*(phi_h) of Xu 2011 Eq. 24 through eval_lobes); RGB.
    glm::dvec3 azimuthal(int p, double phi, double theta_d, double eta) const;
    // Xu et al. 2011, Eq. 9 summed over the roots of the cubic, without the caustic treatment (infinite
    // at a TRT caustic): what the circular Gaussian fits sample (Xu 2011 Eq. 16, 21).
    glm::dvec3 root_azimuthal(int p, double phi, double theta_d, double eta) const;
    // Xu et al. 2011, Eq. 10: A_p at offset h.
    glm::dvec3 attenuation(int p, double h, double theta_d, double eta) const;
    // The white furnace of the model as written (before the division by max(1, E)), RGB, interpolated
    // from the table built at construction (log-spaced towards the poles).
    glm::dvec3 energy(double theta_o) const;
    // Xu 2011 Eq. 24: eta*(phi_h) for the TRT lobe.
    double eccentric_eta(double phi_h) const;
    const HairParams& params() const { return params_; }
    const MarschnerCaustic& caustic() const { return caustic_; }

private:
    glm::dvec3 trt_azimuthal(double phi, double theta_d, double eta) const;

    HairParams params_;
    MarschnerCaustic caustic_;
    std::array<LongitudinalLobe, 3> lobes_;
    // E(theta_o) at theta_o = +-(pi/2 - epsilon_k), epsilon_k log-uniform: [0] for theta_o < 0, [1] above.
    std::array<std::vector<glm::dvec3>, 2> energy_;
};

}  // namespace hairlod::bcsdf
