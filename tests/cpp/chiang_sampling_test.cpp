#include "hairlod/render/chiang_sampling.h"

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "hairlod/bcsdf/furnace.h"
#include "hairlod/render/random.h"

namespace hairlod::render {
namespace {

using bcsdf::ChiangBcsdf;
using bcsdf::HairParams;
constexpr double kPi = std::numbers::pi;

glm::dvec3 direction(double sin_theta, double phi) {
    const double c = std::sqrt(std::max(0.0, 1.0 - sin_theta * sin_theta));
    return {sin_theta, c * std::cos(phi), c * std::sin(phi)};
}

struct Case {
    double theta_o, h, beta_m, beta_n;
};

using Sampler = std::function<BcsdfSample(const std::array<double, 5>&)>;
using Density = std::function<double(const glm::dvec3&)>;

// Histogram of sampled directions over equal-solid-angle bins (uniform in sin(theta) and phi)
// against the bin integrals of the density (8 x 8 midpoints per bin): Pearson's chi-square over
// bins expecting >= 5 samples must stay below dof + 6 sqrt(2 dof) (a > 5 sigma event otherwise).
void expect_histogram_matches(const Sampler& sample, const Density& pdf, const std::string& label) {
    constexpr int kRows = 16, kCols = 32, kSamples = 200000;
    std::vector<double> observed(kRows * kCols, 0.0), expected(kRows * kCols, 0.0);
    Random rng(7, 0, 0);
    for (int k = 0; k < kSamples; ++k) {
        const BcsdfSample s = sample({rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()});
        ASSERT_GT(s.pdf, 0.0) << label;
        EXPECT_NEAR(s.pdf, pdf(s.wi), 1e-9 * s.pdf) << label;
        const glm::dvec3 w = s.wi / glm::length(s.wi);
        const double phi = std::atan2(w.z, w.y);
        const int row = std::min(kRows - 1, static_cast<int>((w.x + 1.0) / 2.0 * kRows));
        const int col = std::min(kCols - 1, static_cast<int>((phi + kPi) / (2.0 * kPi) * kCols));
        observed[row * kCols + col] += 1.0;
    }
    double total = 0.0;
    for (int row = 0; row < kRows; ++row)
        for (int col = 0; col < kCols; ++col) {
            double integral = 0.0;
            const double dz = 2.0 / kRows / 8, dphi = 2.0 * kPi / kCols / 8;
            for (int a = 0; a < 8; ++a)
                for (int b = 0; b < 8; ++b) {
                    const double z = -1.0 + 2.0 * row / kRows + (a + 0.5) * dz;
                    const double phi = -kPi + 2.0 * kPi * col / kCols + (b + 0.5) * dphi;
                    integral += pdf(direction(z, phi)) * dz * dphi;
                }
            expected[row * kCols + col] = integral * kSamples;
            total += integral;
        }
    EXPECT_NEAR(total, 1.0, 0.01) << "pdf integral, " << label;
    double chi2 = 0.0;
    int dof = -1;
    for (size_t k = 0; k < expected.size(); ++k)
        if (expected[k] >= 5.0) {
            chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
            ++dof;
        }
    EXPECT_LT(chi2, dof + 6.0 * std::sqrt(2.0 * dof)) << label;
}

const std::vector<Case> kCases{{0.3, 0.2, 0.3, 0.3}, {-0.8, -0.7, 0.2, 0.5}, {1.45, 0.95, 0.4, 0.3}, {0.0, 0.0, 0.6, 0.8}};

ChiangBcsdf case_bcsdf(const Case& c) {
    HairParams params;
    params.beta_m = c.beta_m;
    params.beta_n = c.beta_n;
    return ChiangBcsdf(params);
}

TEST(ChiangSampling, HistogramMatchesPdf) {
    for (const Case& c : kCases) {
        const ChiangBcsdf bcsdf = case_bcsdf(c);
        const glm::dvec3 wo = direction(std::sin(c.theta_o), 0.4);
        expect_histogram_matches(
            [&](const std::array<double, 5>& u) { return sample_chiang(bcsdf, wo, c.h, {u[0], u[1], u[2], u[3]}); },
            [&](const glm::dvec3& wi) { return chiang_pdf(bcsdf, wi, wo, c.h); },
            "theta_o " + std::to_string(c.theta_o) + " h " + std::to_string(c.h));
    }
}

// The far-field proposal (the aggregated BCSDF's): the mixture over its offsets samples its own
// density, the mean of the offsets' densities.
TEST(ChiangSampling, FarFieldHistogramMatchesPdf) {
    for (const Case& c : kCases) {
        const ChiangBcsdf bcsdf = case_bcsdf(c);
        const glm::dvec3 wo = direction(std::sin(c.theta_o), 0.4);
        expect_histogram_matches([&](const std::array<double, 5>& u) { return sample_chiang_far_field(bcsdf, wo, u); },
                                 [&](const glm::dvec3& wi) { return chiang_far_field_pdf(bcsdf, wi, wo); },
                                 "far field, theta_o " + std::to_string(c.theta_o));
    }
}

// Importance-sampled estimates of integral S cos(theta_i) dw_i: exactly 1 per sample for a lossless
// fibre (the lobe choice follows A_p), and equal to a uniform-sphere estimate for an absorbing one.
TEST(ChiangSampling, EstimatorsAgreeWithEvaluation) {
    HairParams lossless;
    lossless.sigma_a = glm::dvec3(0.0);
    const ChiangBcsdf white(lossless);
    Random rng(3, 1, 0);
    for (double h : {-0.9, 0.0, 0.5}) {
        const glm::dvec3 wo = direction(std::sin(0.6), 1.0);
        for (int k = 0; k < 200; ++k) {
            const BcsdfSample s = sample_chiang(white, wo, h, {rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()});
            EXPECT_NEAR(s.value.x / s.pdf, 1.0, 1e-6);
        }
    }
    HairParams brown;  // default absorption
    const ChiangBcsdf bcsdf(brown);
    const glm::dvec3 wo = direction(std::sin(-0.3), 0.0);
    constexpr int kSamples = 400000;
    glm::dvec3 importance(0.0), uniform(0.0);
    for (int k = 0; k < kSamples; ++k) {
        const BcsdfSample s = sample_chiang(bcsdf, wo, 0.3, {rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()});
        importance += s.value / s.pdf;
        const glm::dvec3 w = direction(2.0 * rng.uniform() - 1.0, 2.0 * kPi * rng.uniform());
        uniform += bcsdf.eval_lobes(w, wo, 0.3).sum() * std::sqrt(1.0 - w.x * w.x) * (4.0 * kPi);
    }
    importance /= double(kSamples);
    uniform /= double(kSamples);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(importance[ch], uniform[ch], 0.02 * uniform[ch] + 2e-3) << ch;
}

}  // namespace
}  // namespace hairlod::render
