#include "hairlod/bcsdf/attenuation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {
namespace {

TEST(Attenuation, LosslessFibreConservesEnergyAtEveryOffset) {
    for (double theta : {-1.5707963, -1.2, 0.0, 0.7, 1.5707963})
        for (double h : {-1.0, -0.999999, -0.5, 0.0, 0.3, 0.9, 1.0}) {
            const FiberAttenuation att = fiber_attenuation(1.55, glm::dvec3(0.0), std::sin(theta), std::cos(theta), h);
            const glm::dvec3 total = att.a[0] + att.a[1] + att.a[2] + att.a[3];
            EXPECT_NEAR(total.x, 1.0, 1e-12) << theta << " " << h;
        }
}

TEST(Attenuation, AbsorptionAndFresnel) {
    const double h = 0.4;
    const FiberAttenuation att = fiber_attenuation(1.55, glm::dvec3(0.0, 1.0, 50.0), 0.0, 1.0, h);
    const double f = fresnel_dielectric(std::sqrt(1.0 - h * h), 1.55);
    EXPECT_NEAR(att.a[0].x, f, 1e-14);
    const double transmittance = std::exp(-2.0 * std::sqrt(1.0 - h * h / (1.55 * 1.55)));
    EXPECT_NEAR(att.a[1].y, (1.0 - f) * (1.0 - f) * transmittance, 1e-14);
    EXPECT_NEAR(att.a[2].y, (1.0 - f) * (1.0 - f) * f * transmittance * transmittance, 1e-14);
    EXPECT_GE(att.a[3].z, 0.0);
    EXPECT_LT(att.a[1].z, 1e-40);
    EXPECT_NEAR(att.gamma_t, std::asin(h / 1.55), 1e-14);
}

TEST(Attenuation, MeanOverOffsetsMatchesAdaptiveQuadrature) {
    for (double theta : {0.0, 0.9, 1.5}) {
        const glm::dvec3 sigma_a{0.1, 0.8, 3.0};
        const auto mean = mean_fiber_attenuation(1.55, sigma_a, std::sin(theta), std::cos(theta));
        for (int p = 0; p < 4; ++p) {
            const glm::dvec3 reference = integrate_adaptive(
                [&](double h) { return 0.5 * fiber_attenuation(1.55, sigma_a, std::sin(theta), std::cos(theta), h).a[p]; },
                -1.0, 1.0, {1e-12, 1e-10, 40});
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[p][c], reference[c], 1e-4 * std::max(1e-3, reference[c]));
        }
    }
}

}  // namespace
}  // namespace hairlod::bcsdf
