#include "hairlod/bcsdf/fiber_frame.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace hairlod::bcsdf {

FiberDirection fiber_direction(const glm::dvec3& w) {
    const double length = glm::length(w);
    const glm::dvec3 u = length > 0.0 ? w / length : glm::dvec3(0.0, 1.0, 0.0);
    FiberDirection d;
    d.sin_theta = std::clamp(u.x, -1.0, 1.0);
    d.cos_theta = std::sqrt(std::max(0.0, u.y * u.y + u.z * u.z));
    d.theta = std::atan2(d.sin_theta, d.cos_theta);
    d.phi = std::atan2(u.z, u.y);
    return d;
}

double wrap_angle(double angle) {
    const double two_pi = 2.0 * std::numbers::pi;
    angle = std::remainder(angle, two_pi);
    return std::clamp(angle, -std::numbers::pi, std::numbers::pi);
}

HalfAngles half_angles(const FiberDirection& wi, const FiberDirection& wo) {
    HalfAngles a;
    a.theta_h = 0.5 * (wi.theta + wo.theta);
    a.theta_d = 0.5 * (wo.theta - wi.theta);
    a.phi = wrap_angle(wo.phi - wi.phi);
    a.phi_h = wi.phi + 0.5 * a.phi;
    return a;
}

double fresnel_dielectric(double cos_incidence, double eta) {
    const double cos_i = std::clamp(std::abs(cos_incidence), 0.0, 1.0);
    const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    const double cos_t = std::sqrt(std::max(0.0, 1.0 - sin2_t));
    const double r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    const double r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (r_s * r_s + r_p * r_p);
}

double bravais_index(double eta, double sin_theta, double cos_theta) {
    return std::sqrt(eta * eta - sin_theta * sin_theta) / std::max(cos_theta, kMinCos);
}

}  // namespace hairlod::bcsdf
