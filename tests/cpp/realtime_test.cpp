#include "hairlod/bcsdf/realtime.h"

#include <gtest/gtest.h>

#include <random>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/marschner.h"

namespace hairlod::bcsdf {
namespace {

TEST(Realtime, ReciprocalInBothVariants) {
    std::mt19937_64 rng(5);
    for (RealtimeTT tt : {RealtimeTT::Tafuri, RealtimeTT::Karis}) {
        const RealtimeBcsdf bcsdf(HairParams{}, tt);
        for (int k = 0; k < 1000; ++k) {
            const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
            const glm::dvec3 a = bcsdf.eval(wi, wo), b = bcsdf.eval(wo, wi);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-9 * std::max(1.0, a[c]));
        }
    }
}

TEST(Realtime, TracksMarschnerLobes) {
    // The approximations keep the lobes where Marschner's are: R and TRT at the back (phi ~ 0),
    // TT in front (phi ~ pi), R colourless, TT and TRT tinted.
    HairParams params;
    params.sigma_a = {0.2, 0.4, 0.9};
    const RealtimeBcsdf rt(params);
    const MarschnerBcsdf exact(params);
    const glm::dvec3 wi = fiber_frame_direction(0.1, 0.0);
    const LobeValues back = rt.eval_lobes(wi, fiber_frame_direction(-0.1, 0.05));
    const LobeValues front = rt.eval_lobes(wi, fiber_frame_direction(-0.1, 3.1));
    EXPECT_GT(front.value[1].x, 10.0 * back.value[1].x);
    EXPECT_GT(back.value[2].x, 10.0 * front.value[2].x);
    EXPECT_DOUBLE_EQ(back.value[0].x, back.value[0].z);
    EXPECT_GT(front.value[1].x, front.value[1].z);
    // Same order of magnitude as the exact TT peak (Tafuri's h = 0 fit).
    const double ratio = front.value[1].x / exact.eval_lobes(wi, fiber_frame_direction(-0.1, 3.1)).value[1].x;
    EXPECT_GT(ratio, 0.2);
    EXPECT_LT(ratio, 5.0);
}

}  // namespace
}  // namespace hairlod::bcsdf
