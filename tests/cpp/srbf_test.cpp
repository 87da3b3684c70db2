#include "hairlod/bcsdf/srbf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/bcsdf/longitudinal.h"

namespace hairlod::bcsdf {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Srbf, LinearQuadratureIsExactForLinearFunctionsAndConvergesForSmoothOnes) {
    const double mu = 0.3, variance = 0.04;
    const std::vector<double> nodes = linear_quadrature_nodes(mu, variance, 4);
    ASSERT_EQ(nodes.size(), 5u);
    EXPECT_DOUBLE_EQ(nodes.front(), -0.5 * kPi);
    EXPECT_NEAR(nodes[2], mu, 1e-15);
    std::vector<glm::dvec3> linear;
    for (double x : nodes) linear.push_back(glm::dvec3(2.0 * x + 1.0));
    const double exact_linear = integrate_adaptive(
        [&](double x) { return gaussian(x - mu, variance) * (2.0 * x + 1.0); }, -0.5 * kPi, 0.5 * kPi, {1e-13, 1e-12, 40});
    EXPECT_NEAR(linear_quadrature(nodes, linear, mu, variance).x, exact_linear, 1e-10);
    // cos^2 x: the m = 4 error is a few percent, m = 16 much smaller (Sec. 4.2.2, Fig. 5).
    const double exact = integrate_adaptive([&](double x) { return gaussian(x - mu, variance) * std::cos(x) * std::cos(x); },
                                            -0.5 * kPi, 0.5 * kPi, {1e-13, 1e-12, 40});
    double previous = 1.0;
    for (int m : {4, 16}) {
        const std::vector<double> n = linear_quadrature_nodes(mu, variance, m);
        std::vector<glm::dvec3> v;
        for (double x : n) v.push_back(glm::dvec3(std::cos(x) * std::cos(x)));
        const double error = std::abs(linear_quadrature(n, v, mu, variance).x - exact) / exact;
        EXPECT_LT(error, m == 4 ? 0.03 : 0.015) << m;
        EXPECT_LT(error, previous);
        previous = error;
    }
}

// The R lobe's polynomial (Xu 2011 Eq. 13) reproduces Marschner's N_R.
TEST(Srbf, RCoefficientsReproduceNR) {
    HairParams params;
    const MarschnerBcsdf marschner(params);
    const CircularGaussianMarschner cg(marschner, test::shared_circular_gaussian_tables());
    double worst = 0.0;
    for (double theta_d : {0.0, 0.7, 1.4})
        for (double phi = -kPi; phi <= kPi; phi += 0.1) {
            const std::array<double, 7> c = cg.r_coefficients(theta_d);
            const double x = std::abs(std::cos(0.5 * phi));
            double fitted = 0.0, power = 1.0;
            for (int k = 0; k < 7; ++k, power *= x) fitted += c[k] * power;
            const double exact = marschner.root_azimuthal(0, phi, theta_d, params.eta).x;
            worst = std::max(worst, std::abs(fitted - exact));
        }
    RecordProperty("worst_nr_absolute", std::to_string(worst));
    EXPECT_LT(worst, 2e-3);
}

// Xu 2011 Eq. 2 / 11 against brute force: the integral of G_j S cos(theta_i) dw_i of the exact Marschner model.
// With m = 4 the worst case is about 20% (relative, floor 1e-3) on the dimmest configurations; the
// error comes from the linear quadrature, the Gaussian stand-in for g^c(theta_i) and the fits.
TEST(Srbf, SingleScatteringMatchesBruteForce) {
    HairParams params;
    params.sigma_a = {0.1, 0.4, 1.2};
    params.beta_m = 0.2;
    const MarschnerBcsdf marschner(params);
    const CircularGaussianMarschner cg(marschner, test::shared_circular_gaussian_tables());
    double worst = 0.0;
    for (double lambda : {0.2, 0.5, 1.0})
        for (const auto& [theta_j, phi_j] : {std::pair{0.2, 0.4}, std::pair{-0.5, 2.8}, std::pair{0.9, -1.5}}) {
            const glm::dvec3 wo = fiber_frame_direction(0.3, 0.0);
            const SrbfLight light{fiber_frame_direction(theta_j, phi_j), lambda, glm::dvec3(1.0)};
            const glm::dvec3 fast = cg.single_scattering(light, wo);
            const glm::dvec3 brute = integrate_directions(
                [&](const glm::dvec3& wi) { return srbf(wi, light.direction, lambda) * marschner.eval(wi, wo); }, -kPi,
                kPi, {1e-6, 1e-4, 20});
            for (int c = 0; c < 3; ++c) {
                const double error = std::abs(fast[c] - brute[c]) / std::max(brute[c], 1e-3);
                worst = std::max(worst, error);
                EXPECT_LT(error, 0.25) << lambda << " " << theta_j << " " << phi_j << " " << c << " " << fast[c] << " " << brute[c];
            }
        }
    RecordProperty("worst_relative", std::to_string(worst));
}

// Narrow lights (lambda = 1e-3) behave as directional lights: S(w_j, w_o) cos(theta_j) pi lambda^2
// (the integral of G cos(theta_i) dw_i for small lambda); wide ones (lambda = 10) stay finite.
TEST(Srbf, NarrowAndWideLights) {
    HairParams params;
    const MarschnerBcsdf marschner(params);
    const CircularGaussianMarschner cg(marschner, test::shared_circular_gaussian_tables());
    const glm::dvec3 wo = fiber_frame_direction(0.3, 0.0);
    const glm::dvec3 wj = fiber_frame_direction(-0.2, 2.9);
    const double lambda = 1e-3;
    const glm::dvec3 narrow = cg.single_scattering({wj, lambda, glm::dvec3(1.0)}, wo);
    const glm::dvec3 directional = cg.eval(wj, wo) * (std::cos(-0.2) * kPi * lambda * lambda);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(narrow[c], directional[c], 0.05 * directional[c]) << c;
    std::mt19937_64 rng(11);
    for (int k = 0; k < 300; ++k) {
        const double l = std::exp(std::log(1e-3) + std::log(1e4) * (k % 50) / 49.0);
        const glm::dvec3 v = cg.single_scattering({test::random_direction(rng), l, glm::dvec3(1.0)}, test::random_direction(rng));
        EXPECT_TRUE(test::finite_non_negative(v)) << l;
    }
    for (const glm::dvec3& a : test::corner_directions())
        EXPECT_TRUE(test::finite_non_negative(cg.single_scattering({a, 10.0, glm::dvec3(1.0)}, wo)));
}

}  // namespace
}  // namespace hairlod::bcsdf
