#include "hairlod/bcsdf/srbf_multiple_scattering.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {
namespace {

constexpr double kPi = std::numbers::pi;

HairParams brown() {
    HairParams params;
    params.sigma_a = {0.2, 0.4, 0.9};
    return params;
}

struct Models {
    MarschnerBcsdf marschner;
    BackscatterTable backscatter;
    SrbfMultipleScattering fast;
    explicit Models(const HairParams& params)
        : marschner(params),
          backscatter(backscatter_table(marschner, 33, kDefaultBackscatterDensity, {1e-5, 1e-4, 24})),
          fast(CircularGaussianMarschner(marschner, test::shared_circular_gaussian_tables()), backscatter) {}
};

const Models& brown_setup() {
    static const Models setup(brown());
    return setup;
}

glm::dvec3 direction(double theta, double phi) { return fiber_frame_direction(theta, phi); }

TEST(SrbfMultipleScattering, BackscatterTableInterpolatesAndAverages) {
    const BackscatterTable& table = brown_setup().backscatter;
    const BackscatterTable::Terms node = table.at(0.0);
    EXPECT_TRUE(test::finite_non_negative(node.A_b));
    // The mean over a tiny interval is the value; over an interval, it lies between the extremes.
    const BackscatterTable::Terms tiny = table.mean(0.3, 0.3);
    const BackscatterTable::Terms value = table.at(0.3);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(tiny.delta_b[c], value.delta_b[c], 1e-12);
    const BackscatterTable::Terms wide = table.mean(-0.4, 0.6);
    for (int c = 0; c < 3; ++c) {
        double lo = 1e9, hi = -1e9;
        for (double t = -0.4; t <= 0.6; t += 0.01) {
            lo = std::min(lo, table.at(t).sigma_b[c]);
            hi = std::max(hi, table.at(t).sigma_b[c]);
        }
        EXPECT_GE(wide.sigma_b[c], lo - 1e-12);
        EXPECT_LE(wide.sigma_b[c], hi + 1e-12);
    }
}

// The fast path (Xu 2011 Eq. 27-31) against the brute-force integral of the same model (exact Marschner fibre,
// exact SRBF) for a narrow, a wide and a nearly uniform light (Xu bandwidths 0.3, 2, 50), several views
// incl. grazing ones; errors relative to the reference total (floored at 1e-3 lambda^2, the light's power scale).
TEST(SrbfMultipleScattering, MatchesBruteForce) {
    const Models& setup = brown_setup();
    const ForwardScattering forward{{0.8, 0.6, 0.4}, 0.05};
    const std::vector<glm::dvec3> views{direction(0.0, 0.3), direction(0.5, 2.6), direction(-0.4, -1.2),
                                        direction(1.35, 0.8), direction(-1.45, 2.9)};
    for (double lambda : {0.3, 2.0, 50.0}) {
        const SrbfLight light{direction(0.3, -0.5), lambda, glm::dvec3(1.0)};
        const std::vector<MultipleScatteringRadiance> reference = srbf_multiple_scattering_reference(
            setup.marschner, setup.backscatter, std::span(&light, 1), std::span(&forward, 1), views,
            kDefaultForwardDensity, 128, 256);
        for (size_t v = 0; v < views.size(); ++v) {
            const MultipleScatteringRadiance fast = setup.fast.eval(light, views[v], forward);
            for (int c = 0; c < 3; ++c) {
                const double scale = std::max(reference[v].total()[c], 1e-3 * light.lambda * light.lambda);
                const double global_error = std::abs(fast.global[c] - reference[v].global[c]) / scale;
                const double local_error = std::abs(fast.local[c] - reference[v].local[c]) / scale;
                // Measured: global within 16% (the grazing view under the narrow light), local within 2%.
                EXPECT_LT(global_error, 0.2) << lambda << " " << v << " " << c;
                EXPECT_LT(local_error, 0.05) << lambda << " " << v << " " << c;
            }
        }
    }
}

TEST(SrbfMultipleScattering, HardCasesAreFiniteAndNonNegative) {
    std::mt19937_64 rng(11);
    for (double sigma_a : {0.0, 50.0}) {
        HairParams params;
        params.sigma_a = glm::dvec3(sigma_a);
        const Models setup(params);
        for (double lambda : {1e-3, 0.1, 2.0, 1e3})
            for (const glm::dvec3& t_f : {glm::dvec3(0.0), glm::dvec3(1.0)})
                for (double variance : {0.0, 1.0}) {
                    std::vector<glm::dvec3> views = test::corner_directions();
                    for (int k = 0; k < 16; ++k) views.push_back(test::random_direction(rng));
                    for (const glm::dvec3& wo : views) {
                        const SrbfLight light{test::random_direction(rng), lambda, glm::dvec3(1.0)};
                        const MultipleScatteringRadiance r = setup.fast.eval(light, wo, {t_f, variance});
                        EXPECT_TRUE(test::finite_non_negative(r.global)) << sigma_a << " " << lambda;
                        EXPECT_TRUE(test::finite_non_negative(r.local)) << sigma_a << " " << lambda;
                        if (t_f == glm::dvec3(0.0)) {
                            EXPECT_EQ(r.total(), glm::dvec3(0.0));
                        }
                    }
                }
    }
}

// A lossless fibre in a white uniform environment (one SRBF with lambda = 1e3, radiance within 4e-6 of
// 1): the forward-scattered light that reaches the point is at most T_f, so the global term (d_f = 1)
// cannot exceed T_f (the fibre's furnace is at most 1), and the local term returns at most the
// fraction d_b A_b of it, A_b <= 1 for a lossless fibre (Zinke et al. 2008's series).
TEST(SrbfMultipleScattering, WhiteFurnaceIsBounded) {
    HairParams params;
    params.sigma_a = glm::dvec3(0.0);
    const MarschnerBcsdf marschner(params);
    const BackscatterTable backscatter = backscatter_table(marschner, 33, kDefaultBackscatterDensity, {1e-5, 1e-4, 24});
    const SrbfMultipleScattering fast(CircularGaussianMarschner(marschner, test::shared_circular_gaussian_tables()), backscatter, 1.0);
    double max_a_b = 0.0;
    for (double t = -0.5 * kPi; t <= 0.5 * kPi; t += 0.01) max_a_b = std::max(max_a_b, backscatter.at(t).A_b.x);
    EXPECT_LE(max_a_b, 1.0);
    const SrbfLight uniform{glm::dvec3(0.0, 1.0, 0.0), 1e3, glm::dvec3(1.0)};
    const double t_f = 0.7;
    for (double theta_o : {-1.5, -0.8, 0.0, 0.4, 1.2, 1.5})
        for (double phi_o : {0.0, 1.0, 2.5}) {
            const MultipleScatteringRadiance r = fast.eval(uniform, direction(theta_o, phi_o), {glm::dvec3(t_f), 0.1});
            for (int c = 0; c < 3; ++c) {
                EXPECT_LE(r.global[c], t_f * 1.02) << theta_o << " " << phi_o;
                EXPECT_LE(r.local[c], t_f * kDefaultBackscatterDensity * max_a_b * 1.02) << theta_o << " " << phi_o;
            }
        }
}

TEST(SrbfMultipleScattering, BadInputsRaiseNamedErrors) {
    const Models& setup = brown_setup();
    const glm::dvec3 wo = direction(0.1, 0.2);
    const auto message = [&](const SrbfLight& light, const ForwardScattering& forward) -> std::string {
        try {
            setup.fast.eval(light, wo, forward);
        } catch (const Error& error) {
            return error.what();
        }
        return "";
    };
    EXPECT_NE(message({direction(0, 0), -1.0, glm::dvec3(1.0)}, {}).find("lambda"), std::string::npos);
    EXPECT_NE(message({direction(0, 0), 1.0, glm::dvec3(1.0)}, {glm::dvec3(1.5), 0.0}).find("forward_attenuation"),
              std::string::npos);
    EXPECT_NE(message({direction(0, 0), 1.0, glm::dvec3(1.0)}, {glm::dvec3(0.5), std::nan("")}).find("forward_variance"),
              std::string::npos);
}

}  // namespace
}  // namespace hairlod::bcsdf
