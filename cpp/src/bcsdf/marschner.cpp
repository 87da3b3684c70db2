#include "hairlod/bcsdf/marschner.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/bcsdf/quadrature.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;

// Coefficients of phi(p, gamma) - p pi = b gamma + a gamma^3 (Marschner et al. 2003, Eq. 10).
struct Cubic {
    double a;
    double b;
};

Cubic deflection_cubic(int p, double eta_prime) {
    const double c = std::asin(std::min(1.0, 1.0 / eta_prime));
    return {-8.0 * p * c / (kPi * kPi * kPi), 6.0 * p * c / kPi - 2.0};
}

double smoothstep(double edge0, double edge1, double x) {
    const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

}  // namespace

AzimuthalRoots marschner_roots(int p, double phi, double eta_prime) {
    AzimuthalRoots roots;
    const double target = wrap_angle(phi - p * kPi);
    if (p == 0) {
        roots.gamma[0] = -0.5 * target;
        roots.count = 1;
        return roots;
    }
    // gamma^3 + P gamma + Q = 0.
    const Cubic cubic = deflection_cubic(p, eta_prime);
    const double P = cubic.b / cubic.a;
    const double Q = -target / cubic.a;
    const double discriminant = 0.25 * Q * Q + P * P * P / 27.0;
    std::array<double, 3> candidates{};
    int candidate_count = 0;
    if (discriminant > 0.0) {
        // Cardano in the form without cancellation: u = -sign(Q) cbrt(|Q|/2 + sqrt(D)), root = u - P / (3u).
        const double u = -std::copysign(std::cbrt(0.5 * std::abs(Q) + std::sqrt(discriminant)), Q);
        candidates[candidate_count++] = u != 0.0 ? u - P / (3.0 * u) : 0.0;
    } else {
        // Three real roots (P < 0): trigonometric form.
        const double m = 2.0 * std::sqrt(-P / 3.0);
        const double angle = std::acos(std::clamp(3.0 * Q / (P * m), -1.0, 1.0)) / 3.0;
        for (int k = 0; k < 3; ++k) candidates[candidate_count++] = m * std::cos(angle - 2.0 * kPi * k / 3.0);
    }
    for (int k = 0; k < candidate_count; ++k)
        if (std::abs(candidates[k]) <= 0.5 * kPi) roots.gamma[roots.count++] = candidates[k];
    return roots;
}

double marschner_dphi_dgamma(int p, double gamma, double eta_prime) {
    if (p == 0) return -2.0;
    const Cubic cubic = deflection_cubic(p, eta_prime);
    return cubic.b + 3.0 * cubic.a * gamma * gamma;
}

MarschnerBcsdf::MarschnerBcsdf(const HairParams& params, const MarschnerCaustic& caustic)
    : params_(params), caustic_(caustic), lobes_(marschner_lobes(params)) {
    params_.validate();
    if (!(caustic_.width > 0.0 && caustic_.width < 2.0 * kPi))
        throw Error("caustic_width must be in (0, 2 pi), got " + std::to_string(caustic_.width));
    if (!(caustic_.fade_range > 0.0 && caustic_.fade_range <= 2.0))
        throw Error("caustic_fade_range must be in (0, 2], got " + std::to_string(caustic_.fade_range));
    if (!(caustic_.max_window > 0.0 && caustic_.max_window <= 2.0))
        throw Error("caustic_max_window must be in (0, 2], got " + std::to_string(caustic_.max_window));
}

double MarschnerBcsdf::eccentric_eta(double phi_h) const {
    const double eta = params_.eta;
    const double a2 = params_.eccentricity * params_.eccentricity;
    const double eta_1 = 2.0 * (eta - 1.0) * a2 - eta + 2.0;
    const double eta_2 = 2.0 * (eta - 1.0) / a2 - eta + 2.0;
    return 0.5 * ((eta_1 + eta_2) + std::cos(2.0 * phi_h) * (eta_1 - eta_2));
}

glm::dvec3 MarschnerBcsdf::attenuation(int p, double h, double theta_d, double eta) const {
    return fiber_attenuation(eta, params_.sigma_a, std::sin(theta_d), std::cos(theta_d), h).a[p];
}

glm::dvec3 MarschnerBcsdf::trt_azimuthal(double phi, double theta_d, double eta) const {
    const double eta_prime = bravais_index(eta, std::sin(theta_d), std::cos(theta_d));
    const Cubic cubic = deflection_cubic(2, eta_prime);
    // Caustic where d phi / d gamma = 0 (Marschner et al. 2003, Sec. 4.3): gamma_c^2 = b / (3 |a|) when
    // eta' < 2; above 2 the two caustics have merged at gamma = 0 and the window fades out.
    const double gamma_c = cubic.b > 0.0 ? std::sqrt(cubic.b / (-3.0 * cubic.a)) : 0.0;
    const double strength = 1.0 - smoothstep(2.0, 2.0 + caustic_.fade_range, eta_prime);
    const double h_c = std::sin(gamma_c);
    const double phi_c = cubic.b * gamma_c + cubic.a * gamma_c * gamma_c * gamma_c;
    // d^2 phi / dh^2 at the caustic = (d^2 phi / d gamma^2) / cos^2(gamma_c).
    const double curvature = std::abs(6.0 * cubic.a * gamma_c) / std::max(1.0 - h_c * h_c, kMinCos);
    const double window = curvature > 0.0
                              ? std::min(caustic_.max_window, 2.0 * std::sqrt(2.0 * caustic_.width / curvature))
                              : caustic_.max_window;
    const double sigma_w = 0.5 * window;
    // 1 - K(h): the fraction of each root kept; K removes a Gaussian window around +-h_c, and
    // vanishes quadratically at h_c so that it cancels the 1 / |d phi / dh| singularity.
    const auto kept = [&](double h) {
        const double d_plus = (h - h_c) / sigma_w;
        const double d_minus = (h + h_c) / sigma_w;
        const double keep_plus = strength < 1.0 ? 1.0 - strength * std::exp(-0.5 * d_plus * d_plus)
                                                : -std::expm1(-0.5 * d_plus * d_plus);
        const double keep_minus = strength < 1.0 ? 1.0 - strength * std::exp(-0.5 * d_minus * d_minus)
                                                 : -std::expm1(-0.5 * d_minus * d_minus);
        return keep_plus * keep_minus;
    };

    glm::dvec3 n(0.0);
    const AzimuthalRoots roots = marschner_roots(2, phi, eta_prime);
    for (int r = 0; r < roots.count; ++r) {
        const double gamma = roots.gamma[r];
        const double h = std::sin(gamma);
        // 1/2 |d phi / dh|^-1 = cos(gamma) / (2 |d phi / d gamma|).
        const double keep = kept(h);
        if (keep <= 0.0) continue;
        const double slope = std::abs(marschner_dphi_dgamma(2, gamma, eta_prime));
        n += (0.5 * std::cos(gamma) * keep / std::max(slope, 1e-300)) * attenuation(2, h, theta_d, eta);
    }
    if (strength <= 0.0) return n;
    const double width2 = caustic_.width * caustic_.width;
    // The removed energy 1/2 integral of A K dh returns as two Gaussian lobes of width w_c at +-phi_c.
    const glm::dvec3 removed = integrate_gauss_legendre(
        [&](double h) { return (0.5 * (1.0 - kept(h))) * attenuation(2, h, theta_d, eta); }, -1.0, 1.0, 4);
    return n + (0.5 * (wrapped_gaussian(phi - phi_c, width2) + wrapped_gaussian(phi + phi_c, width2))) *
                   removed;
}

glm::dvec3 MarschnerBcsdf::azimuthal(int p, double phi, double theta_d, double eta) const {
    if (p == 2) return trt_azimuthal(phi, theta_d, eta);
    const double eta_prime = bravais_index(eta, std::sin(theta_d), std::cos(theta_d));
    const AzimuthalRoots roots = marschner_roots(p, phi, eta_prime);
    glm::dvec3 n(0.0);
    for (int r = 0; r < roots.count; ++r) {
        const double gamma = roots.gamma[r];
        const double slope = std::abs(marschner_dphi_dgamma(p, gamma, eta_prime));
        n += (0.5 * std::cos(gamma) / slope) * attenuation(p, std::sin(gamma), theta_d, eta);
    }
    return n;
}

LobeValues MarschnerBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const HalfAngles angles = half_angles(di, dout);
    const double cos_theta_d = std::max(std::cos(angles.theta_d), kMinCos);
    const double inv_cos2 = 1.0 / (cos_theta_d * cos_theta_d);
    const std::array<double, 3> weight{params_.weight_r, params_.weight_tt, params_.weight_trt};

    LobeValues out;
    out.count = 3;
    for (int p = 0; p < 3; ++p) {
        const double eta = p == 2 ? eccentric_eta(angles.phi_h) : params_.eta;
        const double m = gaussian_longitudinal(di.theta, dout.theta, lobes_[p].shift, lobes_[p].variance);
        out.value[p] = (weight[p] * m * inv_cos2) * azimuthal(p, angles.phi, angles.theta_d, eta);
    }
    return out;
}

}  // namespace hairlod::bcsdf
