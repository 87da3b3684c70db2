#include "hairlod/bcsdf/fiber_rtd.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/bcsdf/longitudinal.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kAttenuationSamples = 257;
// Azimuths over the circle at which the material's TT lobe is integrated (midpoints; the lobe is
// smooth on this scale, its logistic at least 0.1 rad wide).
constexpr int kAzimuthSamples = 720;

// The variance about phi = pi of the material's far-field TT lobe at normal incidence (Chiang et al.
// 2016), energy-weighted over the channels. Its light leaves the fibre at Phi(1, h) = 2 gamma_t -
// 2 gamma_o + pi, which sweeps up to 1.7 rad either side of pi over the offsets h (eta 1.55), and is
// spread further by the logistic. The logistic's variance alone (pi^2 s^2 / 3, an earlier choice)
// left N_TT 8x too narrow in variance for the default brown fibre (0.045 against 0.36 rad^2): a
// thick hair lit from behind returned 4x its strands' light where it peaks and too little off it.
double material_tt_azimuthal_variance(const HairParams& params) {
    HairParams tt_only = params;
    tt_only.weight_r = 0.0;
    tt_only.weight_trt = 0.0;
    const ChiangBcsdf chiang(tt_only);
    const glm::dvec3 wo = fiber_frame_direction(0.0, 0.0);
    double energy = 0.0, moment = 0.0;
    for (int k = 0; k < kAzimuthSamples; ++k) {
        const double phi = 2.0 * kPi * (k + 0.5) / kAzimuthSamples;
        const glm::dvec3 wi = fiber_frame_direction(0.0, phi);
        const glm::dvec3 value = chiang.eval_lobes(wi, wo).value[1];
        const double weight = value.x + value.y + value.z;
        const double offset = wrap_angle(fiber_direction(wo).phi - fiber_direction(wi).phi - kPi);
        energy += weight;
        moment += weight * offset * offset;
    }
    const double logistic = kPi * kPi * logistic_scale(params.beta_n) * logistic_scale(params.beta_n) / 3.0;
    return energy > 0.0 ? std::max(moment / energy, logistic) : logistic;
}

}  // namespace

FiberRtdBcsdf::FiberRtdBcsdf(const HairParams& params) : params_(params) {
    params_.validate();
    const std::array<LongitudinalLobe, 3> marschner = marschner_lobes(params_);
    lobes_ = {marschner[0], marschner[1], LongitudinalLobe{0.0, kPi * kPi / 12.0}};
    azimuthal_variance_ = material_tt_azimuthal_variance(params_);
    const std::array<double, 3> weight{params_.weight_r, params_.weight_tt, params_.weight_trt};
    attenuation_table_.resize(kAttenuationSamples);
    for (int k = 0; k < kAttenuationSamples; ++k) {
        const double theta_d = 0.5 * kPi * k / (kAttenuationSamples - 1);
        const std::array<glm::dvec3, 4> a =
            mean_fiber_attenuation(params_.eta, params_.sigma_a, std::sin(theta_d), std::cos(theta_d));
        attenuation_table_[k] = {weight[0] * a[0], weight[1] * a[1], weight[2] * (a[2] + a[3])};
    }
}

std::array<glm::dvec3, 3> FiberRtdBcsdf::lobe_attenuation(double theta) const {
    // The attenuations are even in theta (they depend on sin^2 and cos).
    const double x = std::min(std::abs(theta), 0.5 * kPi) / (0.5 * kPi) * (kAttenuationSamples - 1);
    const int k = std::min(static_cast<int>(x), kAttenuationSamples - 2);
    const double t = x - k;
    std::array<glm::dvec3, 3> a;
    for (int p = 0; p < 3; ++p) a[p] = (1.0 - t) * attenuation_table_[k][p] + t * attenuation_table_[k + 1][p];
    return a;
}

LobeValues FiberRtdBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    return eval_lobes(wi, wo, RtdSpread{});
}

LobeValues FiberRtdBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, const RtdSpread& spread) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const HalfAngles angles = half_angles(di, dout);
    // A_p at theta_o, which is theta_d on the specular cone (Chiang et al. 2016 take it there too): with
    // unit-energy lobes the lossless fibre then returns A_R + A_TT + A_D = 1 exactly.
    const std::array<glm::dvec3, 3> a = lobe_attenuation(dout.theta);

    // M_p is the rough-cone Gaussian of d'Eon et al. 2011 (tilted by the lobe's shift, Chiang et al.
    // 2016, Sec. 4): close to G(variance, theta_i + theta_o - 2 shift) for narrow lobes, and unit-area
    // under cos(theta_i) dtheta_i at every theta_o, so that with the 1/cos(theta_i) of the measure
    // cos^2(theta_i) dtheta_i dphi_i each lobe returns exactly A_p. A plain Gaussian in theta_i lost the
    // part of the cone cut by the poles and the cos^2(theta_i) weight (lossless furnace 0.10 at theta_o =
    // 1.5). This makes the fibre non-reciprocal in theta (like Chiang's model), not in energy.
    const double inv_cos = 1.0 / std::max(di.cos_theta, kMinCos);
    LobeValues out;
    out.count = 3;
    // Huang 2025 Eq. 8, R: M = G(beta_R, theta_h), N = 1 / (2 pi).
    const double m_r = tilted_deon_longitudinal(di.sin_theta, di.cos_theta, dout.sin_theta, dout.cos_theta,
                                                lobes_[0].shift, lobes_[0].variance + spread.longitudinal_variance);
    out.value[0] = (m_r * inv_cos / (2.0 * kPi)) * (spread.attenuation * a[0]);
    // Huang 2025 Eq. 8, TT: M = G(beta_TT^M, theta_h), N = G(beta_TT^N, phi - pi).
    const double m_tt = tilted_deon_longitudinal(di.sin_theta, di.cos_theta, dout.sin_theta, dout.cos_theta,
                                                 lobes_[1].shift, lobes_[1].variance + spread.longitudinal_variance);
    const double n_tt = wrapped_gaussian(angles.phi - kPi, azimuthal_variance_ + spread.azimuthal_variance);
    out.value[1] = (m_tt * n_tt * inv_cos) * (spread.attenuation * a[1]);
    // Huang 2025 Eq. 8, D: uniform over the sphere.
    out.value[2] = (1.0 / (kPi * kPi)) * (spread.attenuation * a[2]);
    return out;
}

}  // namespace hairlod::bcsdf
