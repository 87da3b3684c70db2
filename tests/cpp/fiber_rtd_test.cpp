#include "hairlod/bcsdf/fiber_rtd.h"

#include <gtest/gtest.h>

#include <random>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/furnace.h"

namespace hairlod::bcsdf {
namespace {

TEST(FiberRtd, LobesFollowEq8) {
    HairParams params;
    params.sigma_a = {0.1, 0.4, 1.0};
    const FiberRtdBcsdf bcsdf(params);
    const glm::dvec3 wi = fiber_frame_direction(0.2, 0.0);
    const LobeValues a = bcsdf.eval_lobes(wi, fiber_frame_direction(-0.3, 0.5));
    const LobeValues b = bcsdf.eval_lobes(wi, fiber_frame_direction(-0.3, 2.5));
    // N_R and N_D are uniform in phi: same theta, different phi, same value.
    EXPECT_NEAR(a.value[0].x, b.value[0].x, 1e-15);
    EXPECT_NEAR(a.value[2].y, b.value[2].y, 1e-15);
    // N_TT peaks at phi = pi.
    EXPECT_GT(b.value[1].x, a.value[1].x);
    // D carries TRT and everything above, averaged over h.
    const auto mean = mean_fiber_attenuation(params.eta, params.sigma_a, std::sin(-0.25), std::cos(-0.25));
    EXPECT_NEAR(a.value[2].z, (mean[2].z + mean[3].z) / (std::numbers::pi * std::numbers::pi),
                1e-5 * a.value[2].z);  // tabulated over theta_d
}

TEST(FiberRtd, ReciprocalAndBoundedEnergy) {
    HairParams params;
    params.sigma_a = glm::dvec3(0.0);
    const FiberRtdBcsdf bcsdf(params);
    std::mt19937_64 rng(11);
    for (int k = 0; k < 1000; ++k) {
        const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
        EXPECT_NEAR(bcsdf.eval(wi, wo).x, bcsdf.eval(wo, wi).x, 1e-12 * std::max(1.0, bcsdf.eval(wi, wo).x));
    }
    for (double theta_o : {0.0, 0.8}) {
        const double e = white_furnace(bcsdf, fiber_frame_direction(theta_o, 0.0), {1e-5, 1e-5, 25}).x;
        RecordProperty("energy_theta_o_" + std::to_string(theta_o), std::to_string(e));
        EXPECT_LE(e, 1.0 + 1e-3);
        EXPECT_GT(e, 0.5);
    }
}

}  // namespace
}  // namespace hairlod::bcsdf
