#include "hairlod/bcsdf/microfacet.h"

#include <cmath>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>


namespace hairlod::bcsdf {
namespace {

constexpr double kPi = std::numbers::pi;

// Brute force: the projected area of the microfacets is the macro surface's, integral of D(m) (m.n) dm = 1,
// by the midpoint rule in u = (1 - cos)^(1/4), which packs nodes near the narrow peak at cos = 1.
TEST(Microfacet, DistributionIsNormalised) {
    for (double alpha : {0.02, 0.1, 0.3, 1.0}) {
        const int n = 200000;
        double sum = 0.0;
        for (int k = 0; k < n; ++k) {
            const double u = (k + 0.5) / n;
            const double c = 1.0 - u * u * u * u, dc = 4.0 * u * u * u / n;
            sum += ggx_distribution(alpha * alpha, c) * c * 2.0 * kPi * dc;
        }
        EXPECT_NEAR(sum, 1.0, 2e-4) << alpha;
    }
}

// Sampling against the density: visible normals drawn for wi have the moments of
// D_wi(h) = G1(wi) max(0, wi.h) D(h) / cos_i (Heitz 2018, Eq. 1), integrated on a fine (theta, phi) grid.
TEST(Microfacet, VisibleNormalSamplesFollowTheirDensity) {
    const glm::dvec3 n(0.0, 0.0, 1.0);
    for (double alpha : {0.1, 0.5}) {
        const double a2 = alpha * alpha;
        const double theta_i = 1.0;
        const glm::dvec3 wi(std::sin(theta_i), 0.0, std::cos(theta_i));
        const double g1 = 1.0 / (1.0 + ggx_lambda(a2, wi.z));
        glm::dvec3 expected(0.0);
        double mass = 0.0;
        const int nt = 2000, np = 400;
        for (int t = 0; t < nt; ++t) {
            const double u = (t + 0.5) / nt;
            const double c = 1.0 - u * u, dc = 2.0 * u / nt;
            const double s = std::sqrt(1.0 - c * c);
            for (int p = 0; p < np; ++p) {
                const double phi = (p + 0.5) * 2.0 * kPi / np;
                const glm::dvec3 h(s * std::cos(phi), s * std::sin(phi), c);
                const double density = g1 * std::max(0.0, glm::dot(wi, h)) * ggx_distribution(a2, c) / wi.z;
                const double w = density * dc * 2.0 * kPi / np;
                expected += w * h;
                mass += w;
            }
        }
        EXPECT_NEAR(mass, 1.0, 2e-3) << alpha;
        std::mt19937_64 engine(3);
        std::uniform_real_distribution<double> uniform(0.0, 1.0);
        glm::dvec3 mean(0.0);
        const int samples = 200000;
        for (int k = 0; k < samples; ++k) {
            const glm::dvec3 h = sample_ggx_visible_normal(alpha, wi, n, uniform(engine), uniform(engine));
            ASSERT_NEAR(glm::length(h), 1.0, 1e-9);
            mean += h / double(samples);
        }
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], expected[c] / mass, 4e-3) << alpha << " " << c;
    }
}

TEST(Microfacet, FresnelAndRefraction) {
    double cos_t = -1.0;
    EXPECT_NEAR(fresnel_dielectric_general(1.0, 1.5, cos_t), 0.04, 1e-12);
    EXPECT_NEAR(cos_t, 1.0, 1e-12);
    // Total internal reflection from inside beyond the critical angle.
    EXPECT_EQ(fresnel_dielectric_general(0.3, 1.0 / 1.5, cos_t), 1.0);
    EXPECT_EQ(cos_t, 0.0);
    // The same interface crossed either way reflects the same (Stokes).
    for (double cos_i : {0.9, 0.5, 0.1}) {
        const double f = fresnel_dielectric_general(cos_i, 1.55, cos_t);
        double back = 0.0;
        EXPECT_NEAR(fresnel_dielectric_general(cos_t, 1.0 / 1.55, back), f, 1e-12);
        EXPECT_NEAR(back, cos_i, 1e-12);
        // Snell: the refracted direction lies in the plane of incidence, sin_t = sin_i / eta.
        const glm::dvec3 wi(std::sqrt(1.0 - cos_i * cos_i), 0.0, cos_i), h(0.0, 0.0, 1.0);
        const glm::dvec3 t = refract_direction(wi, h, cos_i, cos_t, 1.55);
        EXPECT_NEAR(glm::length(t), 1.0, 1e-12);
        EXPECT_NEAR(t.z, -cos_t, 1e-12);
        EXPECT_NEAR(-t.x, wi.x / 1.55, 1e-12);
    }
}

TEST(Microfacet, DielectricAlbedoAndItsEnergyScale) {
    // A smooth interface reflects or transmits everything; a rough one loses energy to the shadowing it
    // does not model, most at grazing light.
    EXPECT_NEAR(ggx_dielectric_albedo(1e-4, 0.7, 1.55), 1.0, 1e-6);
    EXPECT_NEAR(ggx_dielectric_albedo(1e-4, 0.7, 1.0 / 1.55), 1.0, 1e-6);
    const double rough_grazing = ggx_dielectric_albedo(0.8, 0.15, 1.55);
    EXPECT_GT(rough_grazing, 0.3);
    EXPECT_LT(rough_grazing, ggx_dielectric_albedo(0.8, 0.9, 1.55));
    EXPECT_LT(ggx_dielectric_albedo(0.8, 0.9, 1.55), 1.0);
    // The table of one material between its nodes: within 1e-3 of the direct integral, from grazing to
    // normal light, on both sides of the interface.
    for (double alpha : {0.01, 0.3, 0.81}) {
        const DielectricEnergyScale scale(alpha, 1.55);
        for (double cos_i : {0.013, 0.05, 0.2, 0.63, 0.97})
            for (bool inside : {false, true}) {
                const double direct = 1.0 / ggx_dielectric_albedo(alpha, cos_i, inside ? 1.0 / 1.55 : 1.55, 384);
                EXPECT_GE(scale(cos_i, inside), 1.0 - 1e-9);
                EXPECT_NEAR(scale(cos_i, inside) / direct, 1.0, 1e-3) << alpha << " " << cos_i << " " << inside;
            }
    }
}

}  // namespace
}  // namespace hairlod::bcsdf
