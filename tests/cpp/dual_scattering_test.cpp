#include "hairlod/bcsdf/dual_scattering.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hairlod/bcsdf/marschner.h"
#include "hairlod/bcsdf/model_factory.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {
namespace {

TEST(DualScattering, LosslessFibreSplitsAllEnergy) {
    HairParams params;
    params.sigma_a = glm::dvec3(0.0);
    const auto bcsdf = make_bcsdf(BcsdfModel::Chiang, params);
    const std::vector<double> theta_d{0.0, 0.7, 1.4};
    const auto table = dual_scattering_table(*bcsdf, theta_d);
    ASSERT_EQ(table.size(), 3u);
    for (const DualScatteringSample& s : table) {
        // The Chiang fibre is energy conserving: forward + backward = 1.
        EXPECT_NEAR(s.a_f.x + s.a_b.x, 1.0, 2e-3) << s.theta_d;
        // Transmission dominates except at grazing angles, where Fresnel reflection takes over.
        if (s.theta_d < 1.0) {
            EXPECT_GT(s.a_f.x, 2.0 * s.a_b.x);
        }
        // Widths are attenuation-weighted means of the lobes' widths.
        EXPECT_GT(s.beta_b.x, 0.0);
        EXPECT_LT(s.beta_f.x, 0.5 * std::sqrt(4.0 * longitudinal_variance(params.beta_m)) + 1e-12);
    }
}

TEST(DualScattering, ZinkeBackscatteringFormulas) {
    DualScatteringSample s;
    s.a_f = glm::dvec3(0.6);
    s.a_b = glm::dvec3(0.2);
    s.alpha_f = glm::dvec3(0.01);
    s.alpha_b = glm::dvec3(-0.03);
    s.beta_f = glm::dvec3(0.1);
    s.beta_b = glm::dvec3(0.2);
    backscattering_terms(s, 0.7);
    const double one_minus = 1.0 - 0.36;
    EXPECT_NEAR(s.A_1.x, 0.2 * 0.36 / one_minus, 1e-15);
    EXPECT_NEAR(s.A_3.x, 0.008 * 0.36 / (one_minus * one_minus * one_minus), 1e-15);
    EXPECT_NEAR(s.A_b.x, s.A_1.x + s.A_3.x, 1e-15);
    EXPECT_NEAR(s.delta_b.x,
                -0.03 * (1.0 - 2.0 * 0.04 / (one_minus * one_minus)) +
                    0.01 * (2.0 * one_minus * one_minus + 4.0 * 0.36 * 0.04) / std::pow(one_minus, 3),
                1e-15);
    const double expected_sigma = (1.0 + 0.7 * 0.36) *
                                  (0.2 * std::sqrt(0.02 + 0.04) + 0.008 * std::sqrt(0.02 + 0.12)) /
                                  (0.2 + 0.008 * (0.2 + 0.6));
    EXPECT_NEAR(s.sigma_b.x, expected_sigma, 1e-15);
}

TEST(DualScattering, AbsorptionDarkensAndInputsAreChecked) {
    HairParams params;
    params.sigma_a = {0.1, 1.0, 5.0};
    const MarschnerBcsdf bcsdf(params);
    const DualScatteringSample s = dual_scattering(bcsdf, 0.3);
    EXPECT_GT(s.a_f.x, s.a_f.y);
    EXPECT_GT(s.a_f.y, s.a_f.z);
    EXPECT_TRUE(std::isfinite(s.A_b.z) && std::isfinite(s.sigma_b.z));
    EXPECT_THROW(dual_scattering(bcsdf, 2.0), Error);
    EXPECT_THROW(dual_scattering(bcsdf, 0.0, 1.5), Error);
}

}  // namespace
}  // namespace hairlod::bcsdf
