#include "hairlod/bcsdf/chiang.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/bcsdf/quadrature.h"

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

LobeValues ChiangBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const std::array<double, 4> m = longitudinal(di, dout);
    const double phi = di.phi - dout.phi;

    // d'Eon et al. 2011, Sec. 4 (far-field azimuthal scattering): N_p(phi) = 1/2 integral over h of A_p(h) D_p(phi - Phi(p, h)) dh,
    // integrated in gamma_o (dh = cos(gamma_o) d gamma_o), where Phi has a bounded slope.
    const LobeValues integral = integrate_gauss_legendre(
        [&](double gamma_o) {
            const double h = std::sin(gamma_o);
            const FiberAttenuation att =
                fiber_attenuation(params_.eta, params_.sigma_a, dout.sin_theta, dout.cos_theta, h);
            const double jacobian = 0.5 * std::cos(gamma_o);
            LobeValues value;
            value.count = 4;
            for (int p = 0; p < 3; ++p)
                value.value[p] = (jacobian * azimuthal_lobe(phi - deflection(p, att.gamma_o, att.gamma_t))) * att.a[p];
            value.value[3] = (jacobian / (2.0 * kPi)) * att.a[3];
            return value;
        },
        -0.5 * kPi, 0.5 * kPi, panels_);

    const double inv_cos = 1.0 / std::max(di.cos_theta, kMinCos);
    const std::array<double, 4> weight{params_.weight_r, params_.weight_tt, params_.weight_trt, params_.weight_trt};
    LobeValues out;
    out.count = 4;
    for (int p = 0; p < 4; ++p) out.value[p] = (weight[p] * m[p] * inv_cos) * integral.value[p];
    return out;
}

}  // namespace hairlod::bcsdf
