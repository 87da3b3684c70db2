#include "hairlod/bcsdf/chiang.h"

#include <gtest/gtest.h>

#include <random>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {
namespace {

// The white furnace: sigma_a = 0 integrates to 1 within 1e-3 for beta_m, beta_n in {0.1 .. 0.9}.
// Every offset h integrates to 1 (Chiang et al. 2016), so each pair is checked at one (theta_o, h),
// the pairs together covering theta_o in [-1.1, 0.5] and both signs of h.
TEST(Chiang, WhiteFurnaceNearField) {
    HairParams params;
    params.sigma_a = glm::dvec3(0.0);
    double worst = 0.0;
    for (double beta_m : {0.1, 0.3, 0.5, 0.7, 0.9})
        for (double beta_n : {0.1, 0.3, 0.5, 0.7, 0.9}) {
            params.beta_m = beta_m;
            params.beta_n = beta_n;
            const ChiangBcsdf bcsdf(params);
            const double theta_o = -1.2 + 0.1 * (beta_m * 10 + beta_n * 3);
            const double h = beta_n < 0.5 ? 0.37 : -0.91;
            const glm::dvec3 e = white_furnace_near_field(bcsdf, fiber_frame_direction(theta_o, 0.4), h, {1e-6, 1e-6, 30});
            worst = std::max(worst, std::abs(e.x - 1.0));
            EXPECT_NEAR(e.x, 1.0, 1e-3) << beta_m << " " << beta_n;
            EXPECT_NEAR(e.z, e.x, 1e-12);
        }
    RecordProperty("worst_furnace_error", std::to_string(worst));
}

TEST(Chiang, WhiteFurnaceFarFieldAndAbsorption) {
    HairParams params;
    params.sigma_a = glm::dvec3(0.0, 0.5, 5.0);
    params.beta_n = 0.5;
    const ChiangBcsdf bcsdf(params);
    const glm::dvec3 e = white_furnace(bcsdf, fiber_frame_direction(0.5, 1.0), {1e-5, 1e-5, 25});
    EXPECT_NEAR(e.x, 1.0, 1e-3);
    EXPECT_LT(e.y, e.x - 0.05);
    EXPECT_LT(e.z, e.y);
}

// The far field is 1/2 of the near field integrated over h; compare with adaptive quadrature.
TEST(Chiang, FarFieldMatchesAdaptiveIntegralOverH) {
    std::mt19937_64 rng(7);
    for (double beta_n : {0.1, 0.3, 0.9}) {
        HairParams params;
        params.beta_n = beta_n;
        params.sigma_a = {0.2, 0.5, 1.0};
        const ChiangBcsdf bcsdf(params);
        double worst = 0.0;
        for (int k = 0; k < 40; ++k) {
            const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
            const glm::dvec3 reference = integrate_adaptive(
                [&](double gamma) { return 0.5 * std::cos(gamma) * bcsdf.eval_lobes(wi, wo, std::sin(gamma)).sum(); },
                -0.5 * std::numbers::pi, 0.5 * std::numbers::pi, {1e-12, 1e-10, 40});
            const glm::dvec3 value = bcsdf.eval(wi, wo);
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(value[c] - reference[c]) / std::max(reference[c], 1e-2));
        }
        EXPECT_LT(worst, 1e-4) << beta_n;
    }
}

TEST(Chiang, ReducesToCyclesLobeStructure) {
    // With the R weight alone the value is colourless; TT is tinted by absorption.
    HairParams params;
    params.weight_tt = 0.0;
    params.weight_trt = 0.0;
    const ChiangBcsdf r_only(params);
    const glm::dvec3 v = r_only.eval_lobes(fiber_frame_direction(0.2, 0.0), fiber_frame_direction(-0.25, 0.3), 0.1).sum();
    EXPECT_GT(v.x, 0.0);
    EXPECT_DOUBLE_EQ(v.x, v.z);
    const ChiangBcsdf full(HairParams{});
    const LobeValues lobes = full.eval_lobes(fiber_frame_direction(0.2, 0.0), fiber_frame_direction(-0.2, 3.1), 0.0);
    EXPECT_GT(lobes.value[1].x, lobes.value[1].z);
}

}  // namespace
}  // namespace hairlod::bcsdf
