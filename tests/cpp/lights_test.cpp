#include "hairlod/render/lights.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "hairlod/render/random.h"

namespace hairlod::render {
namespace {

constexpr double kPi = std::numbers::pi;

// A 64 x 32 sky: dim blue above, darker ground below, a small bright sun (1000x the sky) at elevation
// 30 degrees, and a black band on the horizon row that must never be drawn.
Environment test_sky(int width = 64, int height = 32) {
    std::vector<glm::vec3> texels(static_cast<size_t>(width) * height);
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c) {
            glm::vec3 t = r < height / 2 ? glm::vec3(0.2f, 0.3f, 0.6f) : glm::vec3(0.05f, 0.04f, 0.03f);
            if (r == height / 2) t = glm::vec3(0.0f);
            if (r == height / 3 && (c == 10 || c == 11)) t = glm::vec3(1000.0f, 900.0f, 800.0f);
            texels[static_cast<size_t>(r) * width + c] = t;
        }
    return Environment(width, height, std::move(texels));
}

double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// The exact integral of the luminance over the sphere for a piecewise-constant equirectangular image:
// texel (r, c) spans azimuth 2 pi / W and elevation from (1/2 - (r + 1) / H) pi to (1/2 - r / H) pi.
double luminance_integral(const Environment& sky, int width, int height) {
    double total = 0.0;
    for (int r = 0; r < height; ++r) {
        const double top = (0.5 - double(r) / height) * kPi, bottom = (0.5 - double(r + 1) / height) * kPi;
        const double solid_angle = 2.0 * kPi / width * (std::sin(top) - std::sin(bottom));
        for (int c = 0; c < width; ++c) {
            const double u = (c + 0.5) / width, v = 1.0 - (r + 0.5) / height;
            const double elevation = (v - 0.5) * kPi, azimuth = -2.0 * kPi * (u - 0.5);
            const glm::vec3 w(float(std::cos(elevation) * std::cos(azimuth)), float(std::cos(elevation) * std::sin(azimuth)),
                              float(std::sin(elevation)));
            total += luminance(sky.radiance(w)) * solid_angle;
        }
    }
    return total;
}

// sample() reports the density pdf() gives at the direction it draws, and draws unit directions.
TEST(EnvironmentSampling, SampleReportsItsOwnDensity) {
    const Environment sky = test_sky();
    Random rng(3, 0, 0);
    for (int k = 0; k < 2000; ++k) {
        const EnvironmentSample s = sky.sample(rng.uniform(), rng.uniform());
        ASSERT_NEAR(glm::length(s.towards), 1.0, 1e-5);
        ASSERT_GT(s.pdf, 0.0);
        EXPECT_NEAR(s.pdf, sky.pdf(s.towards), 1e-6 * s.pdf);
    }
}

// The density integrates to 1 over the sphere (a midpoint rule of 8 x 8 points per texel in (u, v), where
// d omega = 2 pi^2 cos(elevation) du dv: within 1e-3), and is 0 on the black horizon row and on a black image.
TEST(EnvironmentSampling, DensityIsNormalisedAndZeroWhereBlack) {
    const int width = 64, height = 32, per = 8;
    const Environment sky = test_sky(width, height);
    double sum = 0.0;
    for (int j = 0; j < height * per; ++j)
        for (int i = 0; i < width * per; ++i) {
            const double u = (i + 0.5) / (width * per), v = (j + 0.5) / (height * per);
            const double elevation = (v - 0.5) * kPi, azimuth = -2.0 * kPi * (u - 0.5);
            const glm::vec3 w(float(std::cos(elevation) * std::cos(azimuth)), float(std::cos(elevation) * std::sin(azimuth)),
                              float(std::sin(elevation)));
            sum += sky.pdf(w) * 2.0 * kPi * kPi * std::cos(elevation) / (double(width) * per * height * per);
        }
    EXPECT_NEAR(sum, 1.0, 1e-3);
    // The horizon row (row H/2 spans elevations from -pi/32 to 0): just below the horizon.
    EXPECT_EQ(sky.pdf(glm::normalize(glm::vec3(1.0f, 0.3f, -0.02f))), 0.0);
    const Environment black(8, 4, std::vector<glm::vec3>(32, glm::vec3(0.0f)));
    EXPECT_TRUE(black.black());
    EXPECT_EQ(black.pdf(glm::vec3(0.0f, 0.0f, 1.0f)), 0.0);
    EXPECT_EQ(black.sample(0.3, 0.7).pdf, 0.0);
}

// Importance sampling by luminance: the estimate L / pdf of the luminance's integral is unbiased (within
// 0.5 % of the exact integral over 200k samples) and nearly constant (relative standard deviation under
// 0.1, where uniform directions give several times the mean: the sun holds most of the light in 0.2 % of
// the sphere), and no sample lands on the black row.
TEST(EnvironmentSampling, DrawsTheLightInProportionToItsLuminance) {
    const int width = 64, height = 32;
    const Environment sky = test_sky(width, height);
    const double exact = luminance_integral(sky, width, height);
    Random rng(7, 0, 0);
    const int n = 200000;
    double sum = 0.0, sum2 = 0.0, uniform_sum2 = 0.0;
    for (int k = 0; k < n; ++k) {
        const EnvironmentSample s = sky.sample(rng.uniform(), rng.uniform());
        const double value = luminance(sky.radiance(s.towards)) / s.pdf;
        ASSERT_GT(luminance(sky.radiance(s.towards)), 0.0);
        sum += value;
        sum2 += value * value;
        const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi * rng.uniform(), r = std::sqrt(1.0 - z * z);
        const double uniform = luminance(sky.radiance(glm::vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)))) * 4.0 * kPi;
        uniform_sum2 += uniform * uniform;
    }
    const double mean = sum / n;
    EXPECT_NEAR(mean, exact, 0.005 * exact);
    const double deviation = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    EXPECT_LT(deviation, 0.1 * exact);
    const double uniform_deviation = std::sqrt(std::max(0.0, uniform_sum2 / n - exact * exact));
    EXPECT_GT(uniform_deviation, 3.0 * exact);
}

// A constant environment is drawn uniformly over the sphere.
TEST(EnvironmentSampling, ConstantEnvironmentIsUniform) {
    const Environment grey(glm::vec3(0.5f));
    const EnvironmentSample s = grey.sample(0.25, 0.6);
    EXPECT_NEAR(s.pdf, 1.0 / (4.0 * kPi), 1e-12);
    EXPECT_NEAR(grey.pdf(glm::vec3(0.0f, 1.0f, 0.0f)), 1.0 / (4.0 * kPi), 1e-12);
    EXPECT_NEAR(s.towards.z, 0.5f, 1e-6f);
}

}  // namespace
}  // namespace hairlod::render
