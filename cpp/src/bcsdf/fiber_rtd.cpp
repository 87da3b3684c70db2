#include "hairlod/bcsdf/fiber_rtd.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kAttenuationSamples = 257;

}  // namespace

FiberRtdBcsdf::FiberRtdBcsdf(const HairParams& params) : params_(params) {
    params_.validate();
    const std::array<LongitudinalLobe, 3> marschner = marschner_lobes(params_);
    lobes_ = {marschner[0], marschner[1], LongitudinalLobe{0.0, kPi * kPi / 12.0}};
    const double s = logistic_scale(params_.beta_n);
    azimuthal_variance_ = kPi * kPi * s * s / 3.0;
    const std::array<double, 3> weight{params_.weight_r, params_.weight_tt, params_.weight_trt};
    attenuation_table_.resize(kAttenuationSamples);
    for (int k = 0; k < kAttenuationSamples; ++k) {
        const double theta_d = 0.5 * kPi * k / (kAttenuationSamples - 1);
        const std::array<glm::dvec3, 4> a =
            mean_fiber_attenuation(params_.eta, params_.sigma_a, std::sin(theta_d), std::cos(theta_d));
        attenuation_table_[k] = {weight[0] * a[0], weight[1] * a[1], weight[2] * (a[2] + a[3])};
    }
}

std::array<glm::dvec3, 3> FiberRtdBcsdf::lobe_attenuation(double theta_d) const {
    // The attenuations are even in theta_d (they depend on sin^2 and cos).
    const double x = std::min(std::abs(theta_d), 0.5 * kPi) / (0.5 * kPi) * (kAttenuationSamples - 1);
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
    const std::array<glm::dvec3, 3> a = lobe_attenuation(angles.theta_d);

    LobeValues out;
    out.count = 3;
    // Eq. 8, R: M = G(beta_R, theta_h), N = 1 / (2 pi).
    const double m_r = gaussian_longitudinal(di.theta, dout.theta, lobes_[0].shift,
                                             lobes_[0].variance + spread.longitudinal_variance);
    out.value[0] = (m_r / (2.0 * kPi)) * (spread.attenuation * a[0]);
    // Eq. 8, TT: M = G(beta_TT^M, theta_h), N = G(beta_TT^N, phi - pi).
    const double m_tt = gaussian_longitudinal(di.theta, dout.theta, lobes_[1].shift,
                                              lobes_[1].variance + spread.longitudinal_variance);
    const double n_tt = wrapped_gaussian(angles.phi - kPi, azimuthal_variance_ + spread.azimuthal_variance);
    out.value[1] = (m_tt * n_tt) * (spread.attenuation * a[1]);
    // Eq. 8, D: uniform over the sphere.
    out.value[2] = (1.0 / (kPi * kPi)) * (spread.attenuation * a[2]);
    return out;
}

}  // namespace hairlod::bcsdf
