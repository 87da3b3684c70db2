#include "hairlod/bcsdf/longitudinal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hairlod/bcsdf/hair_params.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {
namespace {

constexpr double kHalfPi = 0.5 * std::numbers::pi;

TEST(Longitudinal, LogBesselI0MatchesTheLibraryAndIsContinuous) {
    for (double x : {0.0, 1e-3, 0.5, 3.0, 12.0, 30.0, 49.9, 50.0, 50.1, 200.0, 700.0})
        EXPECT_NEAR(log_bessel_i0(x), std::log(std::cyl_bessel_i(0.0, x)), 1e-12 * std::max(1.0, x)) << x;
    // Far beyond double range of I_0 itself.
    EXPECT_NEAR(log_bessel_i0(1e6), 1e6 - 0.5 * std::log(2.0 * std::numbers::pi * 1e6) + std::log1p(1.0 / 8e6), 1e-6);
}

double normalisation(double sin_o, double cos_o, double shift, double v) {
    return integrate_adaptive(
        [&](double theta_i) {
            return tilted_deon_longitudinal(std::sin(theta_i), std::cos(theta_i), sin_o, cos_o, shift, v) *
                   std::cos(theta_i);
        },
        -kHalfPi, kHalfPi, {1e-12, 1e-12, 40});
}

// The requirement: integral of M_p cos(theta_i) = 1 within 1e-4 for beta_m in [0.05, 1] and
// every theta_o (a 10-term I_0 series misses by about 1.3% at beta_m = 0.3).
TEST(Longitudinal, DeonLobeIsNormalisedForEveryRoughnessAndAngle) {
    double worst = 0.0;
    for (double beta_m = 0.05; beta_m <= 1.0 + 1e-9; beta_m += 0.05)
        for (double theta_o = -kHalfPi; theta_o <= kHalfPi + 1e-9; theta_o += kHalfPi / 12.0)
            for (double variance_scale : {0.25, 1.0, 4.0})  // the TT, R and TRT lobes
                worst = std::max(worst, std::abs(normalisation(std::sin(theta_o), std::cos(theta_o), 0.0,
                                                               variance_scale * longitudinal_variance(beta_m)) - 1.0));
    RecordProperty("worst_normalisation_error", std::to_string(worst));
    EXPECT_LT(worst, 1e-4);
}

// Negative control: the same lobe with I_0 truncated to its first ten series terms (as common
// reference implementations do) misses the normalisation by 1.3% at beta_m = 0.3, theta_o = 0, which the
// test above would catch.
TEST(Longitudinal, TruncatedBesselSeriesWouldFailTheNormalisationTest) {
    const double v = longitudinal_variance(0.3);
    const auto truncated_i0 = [](double x) {
        double term = 1.0, sum = 1.0;
        for (int k = 1; k < 10; ++k) {
            term *= 0.25 * x * x / (double(k) * double(k));
            sum += term;
        }
        return sum;
    };
    const double integral = integrate_adaptive(
        [&](double theta_i) {
            return truncated_i0(std::cos(theta_i) / v) / (2.0 * v * std::sinh(1.0 / v)) *
                   std::cos(theta_i);
        },
        -kHalfPi, kHalfPi, {1e-12, 1e-12, 40});
    RecordProperty("truncated_series_error", std::to_string(integral - 1.0));
    EXPECT_GT(std::abs(integral - 1.0), 5e-3);
    EXPECT_NEAR(normalisation(0.0, 1.0, 0.0, v), 1.0, 1e-12);
}

TEST(Longitudinal, TiltKeepsTheNormalisationAndMovesThePeak) {
    const double v = longitudinal_variance(0.2);
    for (double theta_o : {-1.5, -0.3, 0.0, 0.9, 1.55})
        EXPECT_NEAR(normalisation(std::sin(theta_o), std::cos(theta_o), 0.1, v), 1.0, 1e-9);
    // Centred on theta_i = 2 shift - theta_o.
    const double theta_o = 0.3, shift = -0.05;
    const auto m = [&](double theta_i) {
        return tilted_deon_longitudinal(std::sin(theta_i), std::cos(theta_i), std::sin(theta_o), std::cos(theta_o),
                                        shift, longitudinal_variance(0.05));
    };
    const double peak = 2.0 * shift - theta_o;
    EXPECT_GT(m(peak), m(peak + 0.01));
    EXPECT_GT(m(peak), m(peak - 0.01));
}

TEST(Longitudinal, FiniteForTinyAndHugeVariance) {
    for (double v : {1e-7, longitudinal_variance(1e-3), 1.0, 10.0, 1e5})
        for (double theta_i : {-kHalfPi, -0.5, 0.0, 0.5, kHalfPi})
            for (double theta_o : {-kHalfPi, 0.0, 0.5, kHalfPi}) {
                const double m = deon_longitudinal(std::sin(theta_i), std::cos(theta_i), std::sin(theta_o),
                                                   std::cos(theta_o), v);
                EXPECT_TRUE(std::isfinite(m) && m >= 0.0) << v << " " << theta_i << " " << theta_o;
            }
}

TEST(Longitudinal, GaussianLobeIsUnitAreaInThetaI) {
    const double area = integrate_adaptive([](double t) { return gaussian_longitudinal(t, 0.1, 0.02, 0.01); }, -10.0,
                                           10.0, {1e-12, 1e-12, 40});
    EXPECT_NEAR(area, 1.0, 1e-9);
    EXPECT_NEAR(gaussian_longitudinal(-0.06, 0.1, 0.02, 0.01), gaussian(0.0, 0.01), 1e-12);
}

// Wrapped onto the circle the Gaussian is a density for every variance (the aggregated model adds
// (n - 1) sigma_f^2 up to n = 1e4), and matches the sum over 201 periods on both sides of the switch
// to the Fourier series at variance 4.
TEST(Longitudinal, WrappedGaussianIsADensityForEveryVariance) {
    constexpr double kPi = std::numbers::pi;
    for (double v : {1e-4, 0.1, 1.0, 3.999, 4.001, 10.0, 100.0, 1e4}) {
        const double area =
            integrate_adaptive([&](double x) { return wrapped_gaussian(x, v); }, -kPi, kPi, {1e-12, 1e-12, 40});
        EXPECT_NEAR(area, 1.0, 1e-9) << v;
        if (v > 100.0) continue;
        for (double x : {-3.0, -1.0, 0.0, 0.4, 2.9}) {
            double periods = 0.0;
            for (int k = -100; k <= 100; ++k) periods += gaussian(x + 2.0 * kPi * k, v);
            EXPECT_NEAR(wrapped_gaussian(x, v), periods, 1e-12 * std::max(1.0, periods)) << v << " " << x;
        }
    }
}

}  // namespace
}  // namespace hairlod::bcsdf
