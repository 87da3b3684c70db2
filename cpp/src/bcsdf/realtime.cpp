#include "hairlod/bcsdf/realtime.h"

#include <algorithm>
#include <cmath>

#include <glm/exponential.hpp>
#include <glm/geometric.hpp>

#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"

namespace hairlod::bcsdf {

RealtimeBcsdf::RealtimeBcsdf(const HairParams& params, RealtimeTT tt)
    : params_(params), tt_(tt), lobes_(marschner_lobes(params)) {
    params_.validate();
    log_color_ = -4.0 * params_.sigma_a;
    trt_scale_ = std::clamp(1.5 * (1.0 - params_.beta_n), 0.0, 1.0);
}

LobeValues RealtimeBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const HalfAngles angles = half_angles(di, dout);
    const double eta = params_.eta;
    const double cos_theta_d = std::max(std::cos(angles.theta_d), kMinCos);
    const double cos_phi = std::cos(angles.phi);
    // cos(phi / 2) >= 0 for phi in [-pi, pi] (thesis Eq. 4.13).
    const double cos_half_phi = std::sqrt(std::max(0.0, 0.5 + 0.5 * cos_phi));
    const double lengths = std::max(glm::length(wi) * glm::length(wo), 1e-300);
    const double cos_half_angle = std::sqrt(std::clamp(0.5 + 0.5 * glm::dot(wi, wo) / lengths, 0.0, 1.0));

    std::array<double, 3> m{};
    for (int p = 0; p < 3; ++p)
        m[p] = gaussian_longitudinal(di.theta, dout.theta, lobes_[p].shift, lobes_[p].variance);
    const double inv_cos2 = 1.0 / (cos_theta_d * cos_theta_d);

    LobeValues out;
    out.count = 3;
    // R, thesis Eq. 4.12: F(eta, cos of the half angle between wi and wo) cos(phi/2) / 4.
    out.value[0] = glm::dvec3(params_.weight_r * m[0] * inv_cos2 * fresnel_dielectric(cos_half_angle, eta) *
                              0.25 * cos_half_phi);

    // TT, thesis Eq. 4.22 (Tafuri, h = 0) or Eq. 4.16 + 4.18 (Karis' h_TT); a = 1 / eta'.
    const double a = 1.0 / bravais_index(eta, std::sin(angles.theta_d), cos_theta_d);
    const double h_tt =
        tt_ == RealtimeTT::Karis ? std::clamp((1.0 + a * (0.6 - 0.8 * cos_phi)) * cos_half_phi, -1.0, 1.0) : 0.0;
    const double f_tt = fresnel_dielectric(cos_theta_d * std::sqrt(1.0 - h_tt * h_tt), eta);
    const glm::dvec3 t_tt = glm::exp(log_color_ * (std::sqrt(1.0 - h_tt * h_tt * a * a) / (2.0 * cos_theta_d)));
    const double d_tt = std::exp(-3.65 * cos_phi - 3.98);
    out.value[1] = (params_.weight_tt * m[1] * inv_cos2 * (1.0 - f_tt) * (1.0 - f_tt) * d_tt) * t_tt;

    // TRT, thesis Eq. 4.24-4.28: h = sqrt(3)/2, so cos(gamma_i) = 1/2.
    const double f_trt = fresnel_dielectric(0.5 * cos_theta_d, eta);
    const glm::dvec3 t_trt = glm::exp(log_color_ * (0.8 / cos_theta_d));
    const double d_trt = trt_scale_ * std::exp(trt_scale_ * (17.0 * cos_phi - 16.78));
    out.value[2] = (params_.weight_trt * m[2] * inv_cos2 * (1.0 - f_trt) * (1.0 - f_trt) * f_trt * d_trt) * t_trt;
    return out;
}

}  // namespace hairlod::bcsdf
