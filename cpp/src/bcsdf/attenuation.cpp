#include "hairlod/bcsdf/attenuation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/exponential.hpp>

#include "hairlod/bcsdf/bcsdf.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {

FiberAttenuation fiber_attenuation(double eta, const glm::dvec3& sigma_a, double sin_theta, double cos_theta,
                                   double h) {
    h = std::clamp(h, -1.0, 1.0);
    const double sin_theta_t = sin_theta / eta;
    const double cos_theta_t = std::sqrt(std::max(0.0, 1.0 - sin_theta_t * sin_theta_t));
    const double eta_prime = bravais_index(eta, sin_theta, cos_theta);
    const double sin_gamma_t = std::clamp(h / eta_prime, -1.0, 1.0);
    const double cos_gamma_t = std::sqrt(std::max(0.0, 1.0 - sin_gamma_t * sin_gamma_t));
    const double cos_gamma_o = std::sqrt(std::max(0.0, 1.0 - h * h));

    FiberAttenuation result;
    result.gamma_o = std::asin(h);
    result.gamma_t = std::asin(sin_gamma_t);
    const glm::dvec3 transmittance = glm::exp(-sigma_a * (2.0 * cos_gamma_t / cos_theta_t));
    const double f = fresnel_dielectric(cos_theta * cos_gamma_o, eta);
    result.a[0] = glm::dvec3(f);
    result.a[1] = (1.0 - f) * (1.0 - f) * transmittance;
    result.a[2] = result.a[1] * f * transmittance;
    // Geometric series of the remaining internal reflections: A_2 fT / (1 - fT); fT = 1 only at f = 1,
    // where A_2 = 0.
    for (int c = 0; c < 3; ++c) {
        const double ft = f * transmittance[c];
        result.a[3][c] = ft < 1.0 ? result.a[2][c] * ft / (1.0 - ft) : 0.0;
    }
    return result;
}

std::array<glm::dvec3, 4> mean_fiber_attenuation(double eta, const glm::dvec3& sigma_a, double sin_theta,
                                                 double cos_theta) {
    // In gamma = asin(h) the integrand is smooth up to the rim, where the Fresnel factor turns over.
    const LobeValues sum = integrate_gauss_legendre(
        [&](double gamma) {
            LobeValues s;
            s.count = 4;
            const FiberAttenuation att = fiber_attenuation(eta, sigma_a, sin_theta, cos_theta, std::sin(gamma));
            for (int p = 0; p < 4; ++p) s.value[p] = (0.5 * std::cos(gamma)) * att.a[p];
            return s;
        },
        -0.5 * std::numbers::pi, 0.5 * std::numbers::pi, 8);
    return sum.value;
}

}  // namespace hairlod::bcsdf
