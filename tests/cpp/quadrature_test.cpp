#include "hairlod/bcsdf/quadrature.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hairlod::bcsdf {
namespace {

TEST(Quadrature, GaussLegendreIsExactForPolynomials) {
    // Degree 15 is exact for the 8-point rule on each panel.
    const double value = integrate_gauss_legendre([](double x) { return std::pow(x, 15) + 3.0 * std::pow(x, 14); },
                                                  0.0, 1.0, 1);
    EXPECT_NEAR(value, 1.0 / 16.0 + 3.0 / 15.0, 1e-14);
}

TEST(Quadrature, AdaptiveResolvesNarrowPeaks) {
    // A Gaussian of width 0.05 off the panel centres (a peak narrower than the first rule's node
    // spacing can be missed by any adaptive rule), and an integrable endpoint singularity.
    const double width = 0.05;
    const double peak = integrate_adaptive(
        [&](double x) { return std::exp(-0.5 * (x - 0.3137) * (x - 0.3137) / (width * width)); }, -1.0, 1.0,
        {1e-12, 1e-10, 50});
    EXPECT_NEAR(peak, width * std::sqrt(2.0 * std::numbers::pi), 1e-10);
    const double singular = integrate_adaptive([](double x) { return 1.0 / std::sqrt(x); }, 0.0, 1.0, {1e-9, 1e-9, 60});
    EXPECT_NEAR(singular, 2.0, 1e-6);
}

TEST(Quadrature, VectorValuedAnd2D) {
    const glm::dvec3 v = integrate_adaptive([](double x) { return glm::dvec3(1.0, x, x * x); }, 0.0, 2.0);
    EXPECT_NEAR(v.x, 2.0, 1e-12);
    EXPECT_NEAR(v.y, 2.0, 1e-12);
    EXPECT_NEAR(v.z, 8.0 / 3.0, 1e-12);
    const double area = integrate_adaptive_2d([](double x, double y) { return x * x + y <= 1.0 ? 1.0 : 0.0; }, -1.0,
                                              1.0, 0.0, 1.0, {1e-7, 1e-7, 40});
    EXPECT_NEAR(area, 4.0 / 3.0, 1e-5);
}

}  // namespace
}  // namespace hairlod::bcsdf
