#include "hairlod/bcsdf/circular_gaussian.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/marschner.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {
namespace {

constexpr double kPi = std::numbers::pi;

const CircularGaussianTables& tables() {
    static const CircularGaussianTables t = circular_gaussian_tables();
    return t;
}

// Brute force over one period, split at the lobe centres and +-12 widths around them so that narrow
// lobes are seen by the adaptive rule; `scale` is the expected magnitude (absolute tolerance 1e-10 of it).
template <typename F>
double periodic_integral(F&& f, std::initializer_list<double> centres, double width, double scale) {
    std::vector<double> cuts{-kPi, kPi};
    for (double c : centres)
        for (double offset : {-12.0 * width, 0.0, 12.0 * width})
            if (std::abs(offset) < kPi) cuts.push_back(wrap_angle(c + offset));
    std::sort(cuts.begin(), cuts.end());
    double sum = 0.0;
    for (size_t k = 0; k + 1 < cuts.size(); ++k) sum += integrate_adaptive(f, cuts[k], cuts[k + 1], {1e-10 * scale + 1e-40, 1e-10, 30});
    return sum;
}

TEST(CircularGaussian, IntegralsMatchQuadratureFromNarrowToWide) {
    for (double lambda : {1e-3, 1e-2, 0.3, 1.0, 3.0, 10.0}) {
        const double exact = circular_gaussian_integral(lambda);
        const double numeric = periodic_integral([&](double x) { return circular_gaussian(x, 0.4, lambda); }, {0.4}, lambda, exact);
        EXPECT_NEAR(exact, numeric, 1e-9 * numeric) << lambda;
        EXPECT_NEAR(circular_gaussian_bandwidth(exact), lambda, 1e-9 * lambda) << lambda;
        if (lambda <= 1e-2) {
            EXPECT_NEAR(exact, std::sqrt(kPi) * lambda, 1e-3 * exact);  // the paper's sqrt(pi) lambda
        }
        for (double lambda_2 : {1e-3, 0.5, 10.0})
            for (double mu_2 : {0.0, 1e-3, 2.0, kPi}) {
                const double product = circular_gaussian_product_integral(0.4, lambda, mu_2, lambda_2);
                const double brute = periodic_integral(
                    [&](double x) { return circular_gaussian(x, 0.4, lambda) * circular_gaussian(x, mu_2, lambda_2); },
                    {0.4, mu_2}, std::min(lambda, lambda_2), product);
                EXPECT_NEAR(product, brute, 1e-8 * brute + 1e-38) << lambda << " " << lambda_2 << " " << mu_2;
            }
    }
}

// C_k and H_k tables: exact at the nodes; bilinear lookups between nodes within the stated tolerance.
TEST(CircularGaussian, TablesMatchDirectIntegration) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double worst_c = 0.0, worst_h = 0.0;
    for (int n = 0; n < 200; ++n) {
        const double lambda = std::exp(std::log(1e-3) + u(rng) * std::log(1e4)), phi = kPi * u(rng);
        const int k = n % 7;
        double looked_up[7];
        tables().cosine.lookup(lambda, phi, looked_up);
        const double direct = cosine_gaussian_integral(k, lambda, phi);
        worst_c = std::max(worst_c, std::abs(looked_up[k] - direct) / circular_gaussian_integral(lambda));
        const double eta = std::exp(std::log(10.0) * u(rng)), theta_d = 0.5 * kPi * u(rng);
        double h[3];
        tables().h_trt.lookup(eta, theta_d, h);
        const std::array<double, 3> exact = h_integrals(eta, theta_d, true);
        worst_h = std::max(worst_h, std::abs(h[0] - exact[0]));
    }
    RecordProperty("worst_cosine_relative_to_lobe", std::to_string(worst_c));
    RecordProperty("worst_h_trt_absolute", std::to_string(worst_h));
    EXPECT_LT(worst_c, 0.05);
    EXPECT_LT(worst_h, 1e-2);
    // H_0^TT against adaptive quadrature in h.
    const double eta = 1.55, theta_d = 0.7;
    const double brute = integrate_adaptive(
        [&](double h) {
            const double f = fresnel_dielectric(std::cos(theta_d) * std::sqrt(1.0 - h * h), eta);
            return (1.0 - f) * (1.0 - f) * h * h;
        },
        -1.0, 1.0, {1e-13, 1e-11, 40});
    EXPECT_NEAR(h_integrals(eta, theta_d, false)[1], brute, 1e-7);
}

// Xu 2011 Eq. 16-23 against the Marschner azimuthal functions: energy within the Taylor error, finite everywhere.
TEST(CircularGaussian, FitsPreserveEnergyAcrossTheCaustic) {
    HairParams params;
    params.sigma_a = {0.0, 0.2, 0.6};
    const MarschnerBcsdf marschner(params);
    const double crossing = std::asin(std::sqrt((4.0 - params.eta * params.eta) / 3.0));
    double worst = 0.0;
    for (double theta_d : {0.0, 0.4, crossing - 1e-3, crossing + 1e-3, 1.0, 1.4}) {
        for (int p : {1, 2}) {
            const AzimuthalFit fit = p == 1 ? fit_tt(marschner, tables(), theta_d, params.eta)
                                            : fit_trt(marschner, tables(), theta_d, params.eta);
            const glm::dvec3 fitted = integrate_adaptive([&](double phi) { return fit.eval(phi); }, -kPi, kPi,
                                                         {1e-10, 1e-9, 40});
            const glm::dvec3 exact = integrate_adaptive(
                [&](double h) { return 0.5 * marschner.attenuation(p, h, theta_d, params.eta); }, -1.0, 1.0,
                {1e-12, 1e-10, 40});
            for (int c = 0; c < 3; ++c) {
                const double error = std::abs(fitted[c] - exact[c]) / exact[c];
                worst = std::max(worst, error);
                EXPECT_LT(error, 0.02) << p << " " << theta_d << " " << c;
            }
        }
    }
    RecordProperty("worst_energy_relative", std::to_string(worst));
    // TT peak is N_TT(pi) (Xu 2011 Eq. 16).
    const AzimuthalFit tt = fit_tt(marschner, tables(), 0.3, params.eta);
    EXPECT_NEAR(tt.eval(kPi).y, marschner.root_azimuthal(1, kPi, 0.3, params.eta).y, 1e-9);
    // Continuous across eta' = 2 (Sec. 4.2.4's blend).
    for (double phi = -kPi; phi <= kPi; phi += 0.05) {
        const glm::dvec3 below = fit_trt(marschner, tables(), crossing - 1e-7, params.eta).eval(phi);
        const glm::dvec3 above = fit_trt(marschner, tables(), crossing + 1e-7, params.eta).eval(phi);
        EXPECT_NEAR(below.x, above.x, 1e-3 * std::max(1.0, below.x)) << phi;
    }
}

TEST(CircularGaussian, HardCasesAreFinite) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (double sigma : {0.0, 50.0}) {
        HairParams params;
        params.sigma_a = glm::dvec3(sigma);
        const MarschnerBcsdf marschner(params);
        for (double theta_d : {0.0, 1.0, 0.5 * kPi - 1e-7, -0.5 * kPi})
            for (int p : {1, 2}) {
                const AzimuthalFit fit = p == 1 ? fit_tt(marschner, tables(), theta_d, params.eta)
                                                : fit_trt(marschner, tables(), theta_d, params.eta);
                for (int k = 0; k < 200; ++k) {
                    const double phi = kPi * (2.0 * u(rng) - 1.0), lambda = std::exp(std::log(1e-3) + u(rng) * std::log(1e4));
                    EXPECT_TRUE(test::finite_non_negative(fit.eval(phi)));
                    EXPECT_TRUE(test::finite_non_negative(fit.convolve(phi, lambda)));
                }
            }
    }
}

}  // namespace
}  // namespace hairlod::bcsdf
