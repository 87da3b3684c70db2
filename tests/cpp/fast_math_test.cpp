#include "hairlod/core/fast_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hairlod/core/float4.h"

namespace hairlod {
namespace {

// Stated bounds (fast_math.h), checked against double-precision libm on dense grids.
TEST(FastMath, SinCosWithinOneMicroUnit) {
    double worst = 0.0;
    for (double x = -2000.0; x <= 2000.0; x += 0.0137) {
        const auto xf = static_cast<float>(x);
        const SinCos value = fast_sin_cos(xf);
        worst = std::max({worst, std::abs(value.sin - std::sin(double(xf))), std::abs(value.cos - std::cos(double(xf)))});
    }
    EXPECT_LT(worst, 1e-6);
    EXPECT_EQ(fast_sin_cos(0.0f).sin, 0.0f);
    EXPECT_EQ(fast_sin_cos(0.0f).cos, 1.0f);
}

TEST(FastMath, Log2WithinTheStatedBound) {
    // 2e-7 of the series plus half an ulp of the float result (6e-8 relative).
    double worst = 0.0;
    for (double e = -120.0; e <= 120.0; e += 0.00731) {
        const auto x = static_cast<float>(std::exp2(e));
        const double exact = std::log2(double(x));
        worst = std::max(worst, std::abs(fast_log2(x) - exact) / (2e-7 + 6e-8 * std::abs(exact)));
    }
    EXPECT_LT(worst, 1.0);
    EXPECT_EQ(fast_log2(1.0f), 0.0f);
    EXPECT_EQ(fast_log2(0.5f), -1.0f);
}

TEST(FastMath, Exp2WithinTheStatedBoundAndZeroBelowTheNormals) {
    double worst = 0.0;
    for (double y = -126.0; y <= 127.0; y += 0.00917) {
        const auto yf = static_cast<float>(y);
        worst = std::max(worst, std::abs(fast_exp2(yf) / std::exp2(double(yf)) - 1.0));
    }
    EXPECT_LT(worst, 3e-7);
    EXPECT_EQ(fast_exp2(0.0f), 1.0f);
    EXPECT_EQ(fast_exp2(-127.0f), 0.0f);
    EXPECT_EQ(fast_exp2(-1e30f), 0.0f);
    EXPECT_TRUE(std::isfinite(fast_exp2(1e30f)));
}

TEST(FastMath, PowOfTheUnitInterval) {
    double worst = 0.0;
    for (float p : {0.05f, 0.5f, 1.0f, 2.0f, 3.7f, 8.0f})
        for (int i = 1; i <= 4096; ++i) {
            const float t = static_cast<float>(i) / 4096.0f;
            const double bound = 1e-6 + 6e-8 * std::abs(p * std::log2(double(t)));
            worst = std::max(worst, std::abs(fast_pow_unit(t, p) / std::pow(double(t), double(p)) - 1.0) / bound);
        }
    EXPECT_LT(worst, 1.0);
    EXPECT_EQ(fast_pow_unit(0.0f, 2.0f), 0.0f);
    EXPECT_EQ(fast_pow_unit(1.0f, 5.0f), 1.0f);
}

TEST(Float4, InterleavedStoreWritesPointsInOrder) {
    const Float4 x{0, 3, 6, 9}, y{1, 4, 7, 10}, z{2, 5, 8, 11};
    std::vector<float> out(12, -1.0f);
    store_interleaved4(out.data(), x, y, z);
    for (int i = 0; i < 12; ++i) EXPECT_EQ(out[i], static_cast<float>(i));
}

TEST(Float4, WhereKeepsMaskedLanes) {
    const Float4 value{1, 2, 3, 4};
    const Float4 kept = where4(value > 2.5f, value);
    EXPECT_EQ(kept[0], 0.0f);
    EXPECT_EQ(kept[1], 0.0f);
    EXPECT_EQ(kept[2], 3.0f);
    EXPECT_EQ(kept[3], 4.0f);
}

}  // namespace
}  // namespace hairlod
