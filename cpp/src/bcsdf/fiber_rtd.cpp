#include "hairlod/bcsdf/fiber_rtd.h"

#include <cmath>
#include <numbers>

#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

FiberRtdBcsdf::FiberRtdBcsdf(const HairParams& params) : params_(params) {
    params_.validate();
    const std::array<LongitudinalLobe, 3> marschner = marschner_lobes(params_);
    lobes_ = {marschner[0], marschner[1], LongitudinalLobe{0.0, kPi * kPi / 12.0}};
    const double s = logistic_scale(params_.beta_n);
    azimuthal_variance_ = kPi * kPi * s * s / 3.0;
}

LobeValues FiberRtdBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const HalfAngles angles = half_angles(di, dout);
    const std::array<glm::dvec3, 4> a =
        mean_fiber_attenuation(params_.eta, params_.sigma_a, std::sin(angles.theta_d), std::cos(angles.theta_d));

    LobeValues out;
    out.count = 3;
    // Eq. 8, R: M = G(beta_R, theta_h), N = 1 / (2 pi).
    const double m_r = gaussian_longitudinal(di.theta, dout.theta, lobes_[0].shift, lobes_[0].variance);
    out.value[0] = (params_.weight_r * m_r / (2.0 * kPi)) * a[0];
    // Eq. 8, TT: M = G(beta_TT^M, theta_h), N = G(beta_TT^N, phi - pi).
    const double m_tt = gaussian_longitudinal(di.theta, dout.theta, lobes_[1].shift, lobes_[1].variance);
    out.value[1] = (params_.weight_tt * m_tt * wrapped_gaussian(angles.phi - kPi, azimuthal_variance_)) * a[1];
    // Eq. 8, D: uniform over the sphere.
    out.value[2] = (params_.weight_trt / (kPi * kPi)) * (a[2] + a[3]);
    return out;
}

}  // namespace hairlod::bcsdf
