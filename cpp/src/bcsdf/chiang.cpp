#include "hairlod/bcsdf/chiang.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/bcsdf/quadrature.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;

// Panels of the far-field integral in gamma_o: |dPhi/dgamma_o| <= 2 + 2p/eta' is bounded, so panels of
// width 3s (at least 8) resolve the logistic of scale s; the tests hold this to 1e-4 relative
// against adaptive quadrature.
int panels_for_scale(double s) {
    return std::clamp(static_cast<int>(std::ceil(kPi / (3.0 * s))), 8, 512);
}

}  // namespace

ChiangBcsdf::ChiangBcsdf(const HairParams& params)
    : params_(params), lobes_(chiang_lobes(params)), s_(logistic_scale(params.beta_n)) {
    params_.validate();
    // Chiang et al. 2016, Sec. 4.2 (trimmed logistic): mass of the logistic inside [-pi, pi].
    logistic_normalisation_ = 1.0 / (1.0 + std::exp(-kPi / s_)) - 1.0 / (1.0 + std::exp(kPi / s_));
    panels_ = panels_for_scale(s_);
}

double ChiangBcsdf::deflection(int p, double gamma_o, double gamma_t) {
    return 2.0 * p * gamma_t - 2.0 * gamma_o + p * kPi;
}

double ChiangBcsdf::azimuthal_lobe(double phi) const {
    const double e = std::exp(-std::abs(wrap_angle(phi)) / s_);
    return e / (s_ * (1.0 + e) * (1.0 + e)) / logistic_normalisation_;
}

std::array<double, 4> ChiangBcsdf::longitudinal(const FiberDirection& di, const FiberDirection& dout) const {
    std::array<double, 4> m{};
    for (int p = 0; p < 4; ++p)
        m[p] = tilted_deon_longitudinal(di.sin_theta, di.cos_theta, dout.sin_theta, dout.cos_theta,
                                        lobes_[p].shift, lobes_[p].variance);
    return m;
}

LobeValues ChiangBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, double h) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const std::array<double, 4> m = longitudinal(di, dout);
    const FiberAttenuation att =
                fiber_attenuation(params_.eta, params_.sigma_a, dout.sin_theta, dout.cos_theta, h);
    // Chiang et al. 2016 use phi = phi_i - phi_o with h measured on the outgoing side.
    const double phi = di.phi - dout.phi;
    const double inv_cos = 1.0 / std::max(di.cos_theta, kMinCos);
    const std::array<double, 4> weight{params_.weight_r, params_.weight_tt, params_.weight_trt, params_.weight_trt};

    LobeValues out;
    out.count = 4;
    for (int p = 0; p < 3; ++p) {
        const double n = azimuthal_lobe(phi - deflection(p, att.gamma_o, att.gamma_t));
        out.value[p] = (weight[p] * m[p] * n * inv_cos) * att.a[p];
    }
    out.value[3] = (weight[3] * m[3] * inv_cos / (2.0 * kPi)) * att.a[3];
    return out;
}

LobeValues ChiangBcsdf::far_field_azimuthal(double sin_theta_o, double cos_theta_o, double phi) const {
    // d'Eon et al. 2011, Sec. 4 (far-field azimuthal scattering): N_p(phi) = 1/2 integral over h of A_p(h) D_p(phi - Phi(p, h)) dh,
    // integrated in gamma_o (dh = cos(gamma_o) d gamma_o), where Phi has a bounded slope.
    return integrate_gauss_legendre(
        [&](double gamma_o) {
            const double h = std::sin(gamma_o);
            const FiberAttenuation att = fiber_attenuation(params_.eta, params_.sigma_a, sin_theta_o, cos_theta_o, h);
            const double jacobian = 0.5 * std::cos(gamma_o);
            LobeValues value;
            value.count = 4;
            for (int p = 0; p < 3; ++p)
                value.value[p] = (jacobian * azimuthal_lobe(phi - deflection(p, att.gamma_o, att.gamma_t))) * att.a[p];
            value.value[3] = (jacobian / (2.0 * kPi)) * att.a[3];
            return value;
        },
        -0.5 * kPi, 0.5 * kPi, panels_);
}

LobeValues ChiangBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const std::array<double, 4> m = longitudinal(di, dout);
    const LobeValues integral = far_field_azimuthal(dout.sin_theta, dout.cos_theta, di.phi - dout.phi);
    const double inv_cos = 1.0 / std::max(di.cos_theta, kMinCos);
    const std::array<double, 4> weight{params_.weight_r, params_.weight_tt, params_.weight_trt, params_.weight_trt};
    LobeValues out;
    out.count = 4;
    for (int p = 0; p < 4; ++p) out.value[p] = (weight[p] * m[p] * inv_cos) * integral.value[p];
    return out;
}

LobeValues ChiangBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, const RtdSpread& spread) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const LobeValues azimuthal = far_field_azimuthal(dout.sin_theta, dout.cos_theta, di.phi - dout.phi);
    const std::array<glm::dvec3, 4> attenuation =
        mean_fiber_attenuation(params_.eta, params_.sigma_a, dout.sin_theta, dout.cos_theta);
    const double keep = std::exp(-0.5 * spread.azimuthal_variance);
    const double inv_cos = 1.0 / std::max(di.cos_theta, kMinCos);
    const std::array<double, 4> weight{params_.weight_r, params_.weight_tt, params_.weight_trt, params_.weight_trt};
    LobeValues out;
    out.count = 4;
    for (int p = 0; p < 4; ++p) {
        const double m = tilted_deon_longitudinal(di.sin_theta, di.cos_theta, dout.sin_theta, dout.cos_theta, lobes_[p].shift,
                                                  lobes_[p].variance + spread.longitudinal_variance);
        const glm::dvec3 mean = attenuation[p] / (2.0 * kPi);
        out.value[p] = (weight[p] * m * inv_cos) * spread.attenuation * (mean + keep * (azimuthal.value[p] - mean));
    }
    return out;
}

std::vector<glm::dvec3> far_field_azimuthal_table(const ChiangBcsdf& bcsdf, int theta_samples, int phi_samples) {
    if (theta_samples < 2 || phi_samples < 2)
        throw Error("far_field_azimuthal_table needs at least 2 samples on each axis, got theta_samples = " +
                    std::to_string(theta_samples) + ", phi_samples = " + std::to_string(phi_samples));
    const HairParams& params = bcsdf.params();
    const std::array<double, 4> weight{params.weight_r, params.weight_tt, params.weight_trt, params.weight_trt};
    std::vector<glm::dvec3> table(static_cast<std::size_t>(4) * theta_samples * phi_samples);
    // Rows are independent; each takes 8 x panels fibre paths per node.
    tbb::parallel_for(0, theta_samples, [&](int j) {
        const double theta_o = 0.5 * kPi * j / (theta_samples - 1);
        for (int k = 0; k < phi_samples; ++k) {
            const LobeValues lobes =
                bcsdf.far_field_azimuthal(std::sin(theta_o), std::cos(theta_o), kPi * k / (phi_samples - 1));
            for (int p = 0; p < 4; ++p)
                table[(static_cast<std::size_t>(p) * theta_samples + j) * phi_samples + k] = weight[p] * lobes.value[p];
        }
    });
    return table;
}

}  // namespace hairlod::bcsdf
