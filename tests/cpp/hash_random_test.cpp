#include "hairlod/hairmesh/hash_random.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hairlod {
namespace {

TEST(HashRandom, IsAPureFunctionOfSeedAndKeys) {
    EXPECT_EQ(random_unit(7, 1, 2, 3), random_unit(7, 1, 2, 3));
    EXPECT_NE(random_unit(7, 1, 2, 3), random_unit(8, 1, 2, 3));
    EXPECT_NE(random_unit(7, 1, 2, 3), random_unit(7, 2, 1, 3));
}

TEST(HashRandom, UniformInUnitInterval) {
    RandomStream stream(42);
    double sum = 0.0, sum_sq = 0.0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        const float x = stream.next_unit();
        ASSERT_GE(x, 0.0f);
        ASSERT_LT(x, 1.0f);
        sum += x;
        sum_sq += double(x) * x;
    }
    // Mean 1/2 and variance 1/12 within 5 standard errors.
    EXPECT_NEAR(sum / n, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n));
    EXPECT_NEAR(sum_sq / n - (sum / n) * (sum / n), 1.0 / 12.0, 2e-3);
}

TEST(HashRandom, UnitFloatNeverReachesOne) { EXPECT_LT(unit_float(~uint64_t{0}), 1.0f); }

}  // namespace
}  // namespace hairlod
