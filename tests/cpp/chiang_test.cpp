#include "hairlod/bcsdf/chiang.h"

#include <gtest/gtest.h>

#include <random>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/core/error.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {
namespace {

// The white furnace: sigma_a = 0 integrates to 1 within 1e-3 for beta_m, beta_n in {0.1 .. 0.9}.
// Every offset h integrates to 1 (Chiang et al. 2016), so each pair is checked at one (theta_o, h),
// the pairs together covering theta_o in [-1.1, 0.5] and both signs of h.
TEST(Chiang, WhiteFurnaceNearField) {
    HairParams params;
    params.sigma_a = glm::dvec3(0.0);
    double worst = 0.0;
    for (double beta_m : {0.1, 0.3, 0.5, 0.7, 0.9})
        for (double beta_n : {0.1, 0.3, 0.5, 0.7, 0.9}) {
            params.beta_m = beta_m;
            params.beta_n = beta_n;
            const ChiangBcsdf bcsdf(params);
            const double theta_o = -1.2 + 0.1 * (beta_m * 10 + beta_n * 3);
            const double h = beta_n < 0.5 ? 0.37 : -0.91;
            const glm::dvec3 e = white_furnace_near_field(bcsdf, fiber_frame_direction(theta_o, 0.4), h, {1e-6, 1e-6, 30});
            worst = std::max(worst, std::abs(e.x - 1.0));
            EXPECT_NEAR(e.x, 1.0, 1e-3) << beta_m << " " << beta_n;
            EXPECT_NEAR(e.z, e.x, 1e-12);
        }
    RecordProperty("worst_furnace_error", std::to_string(worst));
}

TEST(Chiang, WhiteFurnaceFarFieldAndAbsorption) {
    HairParams params;
    params.sigma_a = glm::dvec3(0.0, 0.5, 5.0);
    params.beta_n = 0.5;
    const ChiangBcsdf bcsdf(params);
    const glm::dvec3 e = white_furnace(bcsdf, fiber_frame_direction(0.5, 1.0), {1e-5, 1e-5, 25});
    EXPECT_NEAR(e.x, 1.0, 1e-3);
    EXPECT_LT(e.y, e.x - 0.05);
    EXPECT_LT(e.z, e.y);
}

// The far field is 1/2 of the near field integrated over h; compare with adaptive quadrature.
TEST(Chiang, FarFieldMatchesAdaptiveIntegralOverH) {
    std::mt19937_64 rng(7);
    for (double beta_n : {0.1, 0.3, 0.9}) {
        HairParams params;
        params.beta_n = beta_n;
        params.sigma_a = {0.2, 0.5, 1.0};
        const ChiangBcsdf bcsdf(params);
        double worst = 0.0;
        for (int k = 0; k < 40; ++k) {
            const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
            const glm::dvec3 reference = integrate_adaptive(
                [&](double gamma) { return 0.5 * std::cos(gamma) * bcsdf.eval_lobes(wi, wo, std::sin(gamma)).sum(); },
                -0.5 * std::numbers::pi, 0.5 * std::numbers::pi, {1e-12, 1e-10, 40});
            const glm::dvec3 value = bcsdf.eval(wi, wo);
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(value[c] - reference[c]) / std::max(reference[c], 1e-2));
        }
        EXPECT_LT(worst, 1e-4) << beta_n;
    }
}

// The shader's table of the far field's azimuthal parts: at its nodes, weight_p M_p N_p / cos(theta_i)
// rebuilds eval_lobes lobe by lobe; the lower half of theta_o and of phi mirror the table's.
TEST(Chiang, FarFieldTableRebuildsTheFarField) {
    HairParams params;
    params.sigma_a = {0.3, 0.8, 1.6};
    params.weight_tt = 0.7;
    const ChiangBcsdf bcsdf(params);
    const int theta_samples = 9, phi_samples = 13;
    const std::vector<glm::dvec3> table = far_field_azimuthal_table(bcsdf, theta_samples, phi_samples);
    ASSERT_EQ(table.size(), std::size_t(4 * theta_samples * phi_samples));
    const auto lobes = bcsdf.lobe_shapes();
    double worst = 0.0;
    for (int j = 0; j < theta_samples - 1; ++j)  // theta_o = pi / 2 leaves no azimuth
        for (int k = 0; k < phi_samples; ++k)
            for (double sign : {1.0, -1.0}) {
                const double theta_o = sign * 0.5 * std::numbers::pi * j / (theta_samples - 1);
                const double phi = sign * std::numbers::pi * k / (phi_samples - 1);
                const double theta_i = 0.3 - 0.2 * sign;
                const glm::dvec3 wi = fiber_frame_direction(theta_i, phi), wo = fiber_frame_direction(theta_o, 0.0);
                const LobeValues exact = bcsdf.eval_lobes(wi, wo);
                for (int p = 0; p < 4; ++p) {
                    const double m = tilted_deon_longitudinal(std::sin(theta_i), std::cos(theta_i), std::sin(theta_o),
                                                              std::cos(theta_o), lobes[p].shift, lobes[p].variance);
                    const glm::dvec3 rebuilt = (m / std::cos(theta_i)) * table[(p * theta_samples + j) * phi_samples + k];
                    for (int c = 0; c < 3; ++c)
                        worst = std::max(worst, std::abs(rebuilt[c] - exact.value[p][c]) /
                                                    std::max(std::abs(exact.value[p][c]), 1e-12));
                }
            }
    EXPECT_LT(worst, 1e-9);
    EXPECT_THROW(far_field_azimuthal_table(bcsdf, 1, 8), Error);
}

// Light that crossed other hairs first (the aggregated BCSDF's widening, Huang 2025 Eq. 7 and 9): no spread
// is the far field itself; widening keeps each lobe's energy (the white furnace times the attenuation,
// 5e-3) and flattens its azimuthal profile towards its mean.
TEST(Chiang, SpreadFarFieldKeepsEnergyAndFlattens) {
    HairParams params;
    params.sigma_a = {0.25, 0.6, 1.4};
    const ChiangBcsdf bcsdf(params);
    std::mt19937_64 rng(3);
    for (int k = 0; k < 20; ++k) {
        const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
        const LobeValues plain = bcsdf.eval_lobes(wi, wo), spread = bcsdf.eval_lobes(wi, wo, RtdSpread{});
        for (int p = 0; p < 4; ++p)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(spread.value[p][c], plain.value[p][c], 1e-9 * std::max(1.0, std::abs(plain.value[p][c])));
    }

    struct Spread final : FiberBcsdf {
        const ChiangBcsdf& fibre;
        RtdSpread spread;
        Spread(const ChiangBcsdf& f, const RtdSpread& s) : fibre(f), spread(s) {}
        LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override {
            return fibre.eval_lobes(wi, wo, spread);
        }
        std::span<const LongitudinalLobe> lobe_shapes() const override { return fibre.lobe_shapes(); }
        std::string_view name() const override { return "spread"; }
    };
    const RtdSpread wide{0.05, 1.2, glm::dvec3(0.9, 0.7, 0.5)};
    const Spread widened(bcsdf, wide);
    for (double theta_o : {0.0, 0.6, -1.1}) {
        const glm::dvec3 wo = fiber_frame_direction(theta_o, 0.3);
        const glm::dvec3 before = white_furnace(bcsdf, wo, {1e-5, 1e-5, 25});
        const glm::dvec3 after = white_furnace(widened, wo, {1e-5, 1e-5, 25});
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(after[c], wide.attenuation[c] * before[c], 5e-3 * before[c]) << theta_o;
    }
    // The TT lobe seen straight through the fibre (phi = pi) against from the side (phi = pi / 2): the
    // spread brings them together.
    const glm::dvec3 wo = fiber_frame_direction(0.1, 0.0);
    const auto tt = [&](const RtdSpread& s, double phi) {
        return bcsdf.eval_lobes(fiber_frame_direction(-0.1, phi), wo, s).value[1].x;
    };
    const double plain_contrast = tt(RtdSpread{}, std::numbers::pi) / tt(RtdSpread{}, 0.5 * std::numbers::pi);
    const RtdSpread azimuth_only{0.0, 1.2, glm::dvec3(1.0)};
    const double spread_contrast = tt(azimuth_only, std::numbers::pi) / tt(azimuth_only, 0.5 * std::numbers::pi);
    EXPECT_GT(plain_contrast, 1.5);
    EXPECT_LT(spread_contrast, 1.0 + 0.7 * (plain_contrast - 1.0));
    EXPECT_GT(spread_contrast, 1.0);
}

TEST(Chiang, ReducesToCyclesLobeStructure) {
    // With the R weight alone the value is colourless; TT is tinted by absorption.
    HairParams params;
    params.weight_tt = 0.0;
    params.weight_trt = 0.0;
    const ChiangBcsdf r_only(params);
    const glm::dvec3 v = r_only.eval_lobes(fiber_frame_direction(0.2, 0.0), fiber_frame_direction(-0.25, 0.3), 0.1).sum();
    EXPECT_GT(v.x, 0.0);
    EXPECT_DOUBLE_EQ(v.x, v.z);
    const ChiangBcsdf full(HairParams{});
    const LobeValues lobes = full.eval_lobes(fiber_frame_direction(0.2, 0.0), fiber_frame_direction(-0.2, 3.1), 0.0);
    EXPECT_GT(lobes.value[1].x, lobes.value[1].z);
}

}  // namespace
}  // namespace hairlod::bcsdf
