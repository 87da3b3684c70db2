#include "hairlod/bcsdf/marschner.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/common.hpp>
#include <tbb/parallel_for.h>

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

constexpr int kLobeEnergySamples = 257;
constexpr int kFurnaceSamples = 160;
constexpr double kFurnaceMinEpsilon = 1e-7;

// Distance of the k-th furnace sample from the pole, log-uniform in [1e-7, pi/2].
double furnace_epsilon(int k) {
    return kFurnaceMinEpsilon *
           std::pow(0.5 * kPi / kFurnaceMinEpsilon, static_cast<double>(k) / (kFurnaceSamples - 1));
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

    // Integral of N_p over phi = 1/2 integral of A_p over h (Xu et al. 2011, Eq. 9), the largest over
    // the indices Xu 2011 Eq. 24 sweeps, so that the furnace below bounds the eccentric fibre too.
    const std::array<double, 3> weight{params_.weight_r, params_.weight_tt, params_.weight_trt};
    std::vector<std::array<glm::dvec3, 3>> lobe_energy(kLobeEnergySamples);
    for (int k = 0; k < kLobeEnergySamples; ++k) {
        const double theta_d = 0.5 * kPi * k / (kLobeEnergySamples - 1);
        for (double phi_h : {0.0, 0.25 * kPi, 0.5 * kPi}) {
            const std::array<glm::dvec3, 4> a =
                mean_fiber_attenuation(eccentric_eta(phi_h), params_.sigma_a, std::sin(theta_d), std::cos(theta_d));
            for (int p = 0; p < 3; ++p) lobe_energy[k][p] = glm::max(lobe_energy[k][p], weight[p] * a[p]);
        }
    }
    const auto lobe_energy_at = [&](int p, double theta_d) {
        const double x = std::min(std::abs(theta_d), 0.5 * kPi) / (0.5 * kPi) * (kLobeEnergySamples - 1);
        const int k = std::min(static_cast<int>(x), kLobeEnergySamples - 2);
        const double t = x - k;
        return (1.0 - t) * lobe_energy[k][p] + t * lobe_energy[k + 1][p];
    };
    // E(theta_o) = sum_p integral of M_p cos^2(theta_i) / cos^2(theta_d) (integral of N_p) d theta_i,
    // integrated piecewise around each lobe so that narrow lobes (beta_m = 1e-3) are resolved.
    const auto furnace = [&](double theta_o) {
        glm::dvec3 e(0.0);
        for (int p = 0; p < 3; ++p) {
            const auto integrand = [&](double theta_i) {
                const double c = std::max(std::cos(0.5 * (theta_o - theta_i)), kMinCos);
                const double cos_i = std::cos(theta_i);
                return (gaussian_longitudinal(theta_i, theta_o, lobes_[p].shift, lobes_[p].variance) * cos_i * cos_i /
                        (c * c)) * lobe_energy_at(p, 0.5 * (theta_o - theta_i));
            };
            const double centre = std::clamp(2.0 * lobes_[p].shift - theta_o, -0.5 * kPi, 0.5 * kPi);
            const double window = 10.0 * std::sqrt(lobes_[p].variance);
            // Also cut at theta_d = 0, where the even attenuation table has a kink.
            std::array<double, 6> cuts{-0.5 * kPi, std::max(-0.5 * kPi, centre - window), centre,
                                       std::min(0.5 * kPi, centre + window), 0.5 * kPi, theta_o};
            std::sort(cuts.begin(), cuts.end());
            for (size_t k = 0; k + 1 < cuts.size(); ++k)
                if (cuts[k + 1] > cuts[k]) e += integrate_adaptive(integrand, cuts[k], cuts[k + 1], {1e-6, 1e-6, 20});
        }
        return e;
    };
    for (int side = 0; side < 2; ++side) {
        energy_[side].resize(kFurnaceSamples);
        tbb::parallel_for(0, kFurnaceSamples, [&](int k) {
            const double theta_o = (side == 0 ? -1.0 : 1.0) * (0.5 * kPi - furnace_epsilon(k));
            energy_[side][k] = furnace(theta_o);
        });
    }
}

glm::dvec3 MarschnerBcsdf::energy(double theta_o) const {
    // Inverse of furnace_epsilon, linear in log(epsilon).
    const double epsilon = std::clamp(0.5 * kPi - std::abs(theta_o), kFurnaceMinEpsilon, 0.5 * kPi);
    const double x = std::log(epsilon / kFurnaceMinEpsilon) / std::log(0.5 * kPi / kFurnaceMinEpsilon) *
                     (kFurnaceSamples - 1);
    const int k = std::min(static_cast<int>(x), kFurnaceSamples - 2);
    const double t = x - k;
    const std::vector<glm::dvec3>& table = energy_[theta_o < 0.0 ? 0 : 1];
    return (1.0 - t) * table[k] + t * table[k + 1];
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
    return p == 2 ? trt_azimuthal(phi, theta_d, eta) : root_azimuthal(p, phi, theta_d, eta);
}

glm::dvec3 MarschnerBcsdf::root_azimuthal(int p, double phi, double theta_d, double eta) const {
    const double eta_prime = bravais_index(eta, std::sin(theta_d), std::cos(theta_d));
    const AzimuthalRoots roots = marschner_roots(p, phi, eta_prime);
    glm::dvec3 n(0.0);
    for (int r = 0; r < roots.count; ++r) {
        const double gamma = roots.gamma[r];
        const double slope = std::abs(marschner_dphi_dgamma(p, gamma, eta_prime));
        n += (0.5 * std::cos(gamma) / std::max(slope, 1e-300)) * attenuation(p, std::sin(gamma), theta_d, eta);
    }
    return n;
}

LobeValues MarschnerBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const HalfAngles angles = half_angles(di, dout);
    const double cos_theta_d = std::max(std::cos(angles.theta_d), kMinCos);
    const glm::dvec3 excess = glm::max(energy(dout.theta), glm::dvec3(1.0));
    const glm::dvec3 inv_cos2 = 1.0 / (cos_theta_d * cos_theta_d * excess);
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
