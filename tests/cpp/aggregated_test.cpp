#include "hairlod/bcsdf/aggregated.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>

#include <glm/exponential.hpp>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {
namespace {

constexpr double kPi = std::numbers::pi;

HairParams brown() {
    HairParams p;
    p.sigma_a = {0.2, 0.5, 1.2};
    return p;
}

const std::shared_ptr<const AggregatedTable>& brown_table() {
    static const auto table = std::make_shared<const AggregatedTable>(aggregated_table(FiberRtdBcsdf(brown())));
    return table;
}

// The paper (Sec. 4): with n = 1 and the ray leaving through the back, the model is the single fibre.
TEST(Aggregated, ReducesToTheSingleFibreThroughTheBack) {
    const FiberRtdBcsdf fiber(brown());
    std::mt19937_64 rng(9);
    int checked = 0;
    for (double density : {1e-4, 0.3, 1.0}) {
        const AggregatedBcsdf aggregated(brown(), {1.0, density}, brown_table());
        for (int k = 0; k < 2000; ++k) {
            const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
            if (std::abs(half_angles(fiber_direction(wi), fiber_direction(wo)).phi) <= 0.5 * kPi) continue;
            const glm::dvec3 a = aggregated.eval(wi, wo), b = fiber.eval(wi, wo);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-12 * std::max(1.0, b[c]));
            ++checked;
        }
    }
    EXPECT_GT(checked, 2000);
}

// A renderer evaluates one model at each hit's n and rho: it must equal the model built for them.
TEST(Aggregated, EvaluationAtAnyStateEqualsTheModelBuiltForIt) {
    const AggregatedBcsdf shared(brown(), {}, brown_table());
    std::mt19937_64 rng(21);
    for (const ClusterState state : {ClusterState{1.0, 1.0}, ClusterState{1.7, 0.05}, ClusterState{12.3, 0.4},
                                     ClusterState{300.0, 0.9}}) {
        const AggregatedBcsdf built(brown(), state, brown_table());
        for (int k = 0; k < 500; ++k) {
            const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
            const LobeValues a = shared.eval_lobes(wi, wo, state), b = built.eval_lobes(wi, wo);
            ASSERT_EQ(a.count, b.count);
            for (int p = 0; p < a.count; ++p) EXPECT_EQ(a.value[p], b.value[p]) << state.hair_count << " " << p;
        }
    }
    EXPECT_THROW(shared.eval_lobes(glm::dvec3(0, 0, 1), glm::dvec3(0, 0, 1), {0.5, 0.5}), Error);
    EXPECT_THROW(shared.eval_lobes(glm::dvec3(0, 0, 1), glm::dvec3(0, 0, 1), {2.0, 0.0}), Error);
}

// On the material's fibre (the preview's): through the back it is the Chiang far field; towards the front
// it adds the same B^ as on the R, TT, D fibre; lossless, the energy stays bounded as on that fibre.
TEST(Aggregated, OnTheMaterialsFibre) {
    const ChiangBcsdf material(brown());
    const AggregatedBcsdf on_rtd(brown(), {1.0, 1.0}, brown_table());
    const AggregatedBcsdf on_material(brown(), {1.0, 1.0}, brown_table(), AggregatedFibre::Material);
    std::mt19937_64 rng(19);
    int back = 0, front = 0;
    for (int k = 0; k < 400; ++k) {
        const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
        const LobeValues a = on_material.eval_lobes(wi, wo), fibre = material.eval_lobes(wi, wo);
        const glm::dvec3 direct = a.value[0] + a.value[1] + a.value[2], expected = fibre.sum();
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(direct[c], expected[c], 1e-12 * std::max(1.0, expected[c]));
        const glm::dvec3 b_material = a.value[3], b_rtd = on_rtd.eval_lobes(wi, wo).value[3];
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(b_material[c], b_rtd[c], 1e-12 * std::max(1.0, b_rtd[c]));
        (std::abs(half_angles(fiber_direction(wi), fiber_direction(wo)).phi) < 0.5 * kPi ? front : back) += 1;
    }
    EXPECT_GT(front, 100);
    EXPECT_GT(back, 100);

    HairParams lossless;
    lossless.sigma_a = glm::dvec3(0.0);
    const auto table = std::make_shared<const AggregatedTable>(aggregated_table(FiberRtdBcsdf(lossless)));
    for (double n : {1.0, 3.0, 40.0}) {
        // Both fibres hold the material's energy: the same furnace within the quadrature's and the R, TT, D
        // fibre's tabulated attenuations' error.
        const AggregatedBcsdf aggregated(lossless, {n, 0.5}, table, AggregatedFibre::Material);
        const AggregatedBcsdf reference(lossless, {n, 0.5}, table);
        const glm::dvec3 wo = fiber_frame_direction(0.3, 0.0);
        const double e = white_furnace(aggregated, wo, {3e-4, 3e-4, 16}).x;
        const double e_rtd = white_furnace(reference, wo, {3e-4, 3e-4, 16}).x;
        RecordProperty("lossless_energy_n_" + std::to_string(n), std::to_string(e) + " (rtd " + std::to_string(e_rtd) + ")");
        EXPECT_LE(e, 1.0 + 2e-3) << n;
        EXPECT_NEAR(e, e_rtd, 0.02) << n;
    }
}

TEST(Aggregated, ShadowingMaskingEq12To15) {
    const AggregatedBcsdf aggregated(brown(), {2.0, 0.25}, brown_table());
    const glm::dvec3 a_f{0.5, 0.3, 0.1};
    const double phi = 0.7;
    const double p_s = 0.75 * (1.0 - std::cos(phi)), p_m = 0.75 * kMultipleShadowing;
    const glm::dvec3 s = aggregated.shadowing_masking(phi, a_f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s[c], p_s * a_f[c] + (1.0 - p_m - p_s), 1e-15);
    EXPECT_EQ(aggregated.shadowing_masking(2.0, a_f), glm::dvec3(1.0));
    // Sparse clusters near phi = pi/2: the probabilities stay in [0, 1], so S stays non-negative.
    const AggregatedBcsdf sparse(brown(), {2.0, 1e-4}, brown_table());
    const glm::dvec3 edge = sparse.shadowing_masking(0.5 * kPi - 1e-9, glm::dvec3(0.0));
    EXPECT_GE(edge.x, 0.0);
}

TEST(Aggregated, BackLobeFollowsEq10And11) {
    const double n = 3.0;
    const AggregatedBcsdf aggregated(brown(), {n, 1.0}, brown_table());
    const glm::dvec3 wi = fiber_frame_direction(0.1, 0.0), wo = fiber_frame_direction(-0.1, 0.2);
    const LobeValues lobes = aggregated.eval_lobes(wi, wo);
    const DualScatteringSample hair = brown_table()->sample(-0.1);
    const double a_f = hair.a_f.x;
    const double a_1_plus = kSideScatterWeight * hair.a_b.x * (a_f + std::pow(a_f, 3) + std::pow(a_f, 5));
    const double m = gaussian_longitudinal(0.1, -0.1, hair.delta_b.x, 4.0 * hair.sigma_b.x * hair.sigma_b.x);
    const double shadowing = aggregated.shadowing_masking(0.2, hair.a_f).x;  // rho = 1: P_n = 1
    EXPECT_NEAR(shadowing, 1.0, 1e-15);
    const double budget = 1.0 - std::pow(a_f, n - 1.0) * (hair.a_f.x + hair.a_b.x);
    EXPECT_LT(a_1_plus + hair.A_1.x + hair.A_3.x, budget);  // this absorbing hair is under its budget
    EXPECT_NEAR(lobes.value[3].x, (a_1_plus + hair.A_1.x + hair.A_3.x) * m / kPi, 1e-12);
    // No back lobe in front (|phi| > pi/2).
    EXPECT_EQ(aggregated.eval_lobes(wi, fiber_frame_direction(-0.1, 2.5)).value[3], glm::dvec3(0.0));
}

// Shaded inside by a path tracer (render/integrator.cpp): R^, TT^, D^ are the fibre's behind k = the
// light's crossings (attenuation E[a_F^k] over a Poisson count, Huang 2025 Eq. 9's spread with n - 1 = k, along the fibre by beta_f^2), and B^
// is A_1+ over the hair_count - 1 strands behind alone (A_1 + A_3 are on the traced paths).
TEST(Aggregated, ShadedInsideTakesTheLightsCrossingsAndKeepsOnlyA1Plus) {
    const FiberRtdBcsdf fiber(brown());
    const AggregatedBcsdf aggregated(brown(), {}, brown_table());
    std::mt19937_64 rng(5);
    int front = 0;
    for (int k = 0; k < 3000 && front < 400; ++k) {
        const glm::dvec3 wi = test::random_direction(rng), wo = test::random_direction(rng);
        const HalfAngles angles = half_angles(fiber_direction(wi), fiber_direction(wo));
        if (std::abs(angles.phi) <= 0.5 * kPi) continue;
        ++front;
        // No crossing: the fibre itself, whatever the strands behind.
        const glm::dvec3 alone = aggregated.eval_lobes(wi, wo, {7.0, 1.0, true, 0.0}).sum(), fibre = fiber.eval(wi, wo);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(alone[c], fibre[c], 1e-12 * std::max(1.0, fibre[c]));
        // k = 2.5 crossings.
        const double crossings = 2.5;
        const DualScatteringSample hair = brown_table()->sample(angles.theta_d);
        const glm::dvec3 sigma_f2 = brown_table()->azimuthal_variance(angles.theta_d);
        const double sigma_f2_mean = (sigma_f2.x + sigma_f2.y + sigma_f2.z) / 3.0;
        RtdSpread spread;
        spread.attenuation = glm::exp(-crossings * (1.0 - hair.a_f));
        const glm::dvec3 beta_f2 = hair.beta_f * hair.beta_f;
        // Along the fibre the lobes widen by dual scattering's beta_f^2, across it by sigma_f^2.
        spread.longitudinal_variance = 4.0 * crossings * (beta_f2.x + beta_f2.y + beta_f2.z) / 3.0;
        spread.azimuthal_variance = crossings * sigma_f2_mean;
        const glm::dvec3 behind = aggregated.eval_lobes(wi, wo, {1.0, 1.0, true, crossings}).sum();
        const glm::dvec3 expected = fiber.eval_lobes(wi, wo, spread).sum();
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(behind[c], expected[c], 1e-12 * std::max(1.0, expected[c]));
    }
    EXPECT_EQ(front, 400);

    // hair_count 3: the shaded strand and 2 behind it, so the series has 2 terms; none behind, no B^.
    const double n = 3.0;
    const glm::dvec3 wi = fiber_frame_direction(0.1, 0.0), wo = fiber_frame_direction(-0.1, 0.2);
    const DualScatteringSample hair = brown_table()->sample(-0.1);
    const double a_f = hair.a_f.x;
    const double a_1_plus = kSideScatterWeight * hair.a_b.x * (a_f + std::pow(a_f, 3));
    const double m = gaussian_longitudinal(0.1, -0.1, hair.delta_b.x, 4.0 * hair.sigma_b.x * hair.sigma_b.x);
    EXPECT_NEAR(aggregated.eval_lobes(wi, wo, {n, 1.0, true, 0.0}).value[3].x, a_1_plus * m / kPi, 1e-12);
    EXPECT_EQ(aggregated.eval_lobes(wi, wo, {1.0, 1.0, true, 0.0}).value[3], glm::dvec3(0.0));
    EXPECT_THROW(aggregated.eval_lobes(wi, wo, {n, 1.0, true, -1.0}), Error);
    EXPECT_THROW(aggregated.eval_lobes(wi, wo, {n, 1.0, true, std::nan("")}), Error);
}

// The same energy bound shaded inside: lossless, any crossings and strands behind, grazing included.
TEST(Aggregated, ShadedInsideLosslessEnergyNeverExceedsOne) {
    HairParams lossless;
    lossless.sigma_a = glm::dvec3(0.0);
    const auto table = std::make_shared<const AggregatedTable>(aggregated_table(FiberRtdBcsdf(lossless)));
    const AggregatedBcsdf aggregated(lossless, {}, table);
    for (double n : {1.0, 3.0, 1e4})
        for (double crossings : {0.0, 1.0, 50.0})
            for (double theta_o : {-0.5 * kPi + 1e-4, 0.3, 1.4}) {
                const ClusterState state{n, 1.0, true, crossings};
                const AggregatedBcsdf built(lossless, state, table);
                const double e = white_furnace(built, fiber_frame_direction(theta_o, 0.0), {3e-4, 3e-4, 16}).x;
                EXPECT_LE(e, 1.0 + 1e-3) << n << " " << crossings << " " << theta_o;
                EXPECT_TRUE(std::isfinite(e) && e >= 0.0);
            }
}

TEST(Aggregated, MoreHairsDarkenAndEnergyIsBounded) {
    double previous = 2.0;
    for (double n : {1.0, 2.0, 8.0, 1e4}) {
        const AggregatedBcsdf aggregated(brown(), {n, 0.5}, brown_table());
        const glm::dvec3 e = white_furnace(aggregated, fiber_frame_direction(0.3, 0.0), {1e-4, 1e-4, 20});
        RecordProperty("energy_n_" + std::to_string(int(n)), std::to_string(e.x));
        EXPECT_LE(e.x, 1.0 + 1e-3);
        EXPECT_LT(e.x, previous);
        EXPECT_TRUE(test::finite_non_negative(e));
        previous = e.x;
    }
}

// Energy bound: B^ adds light returned by neighbours on top of the hair's own lobes; capped by the
// budget it never lifts the lossless aggregate above 1 (it reached 1.04 at n = 1 without the cap),
// for n from 1 to 1e4, rho from 1e-4 to 1 and grazing theta_o.
TEST(Aggregated, LosslessEnergyNeverExceedsOne) {
    HairParams lossless;
    lossless.sigma_a = glm::dvec3(0.0);
    const auto table = std::make_shared<const AggregatedTable>(aggregated_table(FiberRtdBcsdf(lossless)));
    double highest = 0.0;
    for (double n : {1.0, 1.5, 3.0, 1e4})
        for (double density : {1e-4, 0.5, 1.0})
            for (double theta_o : {-0.5 * kPi + 1e-4, 0.3, 1.4}) {
                const AggregatedBcsdf aggregated(lossless, {n, density}, table);
                const double e = white_furnace(aggregated, fiber_frame_direction(theta_o, 0.0), {3e-4, 3e-4, 16}).x;
                highest = std::max(highest, e);
                EXPECT_LE(e, 1.0 + 1e-3) << n << " " << density << " " << theta_o;
                EXPECT_TRUE(std::isfinite(e) && e >= 0.0);
            }
    RecordProperty("highest_lossless_energy", std::to_string(highest));
    EXPECT_GT(highest, 0.8);
}

// The paper's reduction (Sec. 4) in energy: one lossless hair (n = 1) in a full cluster (rho = 1, so
// S = 1) returns what the fibre returns, 1 within 2e-3 (the B^ budget 1 - (a_f + a_b) is the
// quadrature residue of the table), up to grazing theta_o and for several roughnesses.
TEST(Aggregated, LosslessSingleHairFurnaceIsOne) {
    for (double beta : {0.1, 0.3, 0.7}) {
        HairParams lossless;
        lossless.sigma_a = glm::dvec3(0.0);
        lossless.beta_m = beta;
        lossless.beta_n = beta;
        const auto table = std::make_shared<const AggregatedTable>(aggregated_table(FiberRtdBcsdf(lossless)));
        const AggregatedBcsdf aggregated(lossless, {1.0, 1.0}, table);
        for (double theta_o : {0.0, 0.5, 1.0, 1.4, 1.55}) {
            const double e = white_furnace(aggregated, fiber_frame_direction(theta_o, 0.0), {1e-5, 1e-5, 22}).x;
            RecordProperty("energy_beta_" + std::to_string(beta) + "_theta_o_" + std::to_string(theta_o),
                           std::to_string(e));
            EXPECT_NEAR(e, 1.0, 2e-3) << beta << " " << theta_o;
            EXPECT_LE(e, 1.0 + 1e-3) << beta << " " << theta_o;
        }
    }
}

TEST(Aggregated, ClusterGeometry) {
    EXPECT_NEAR(cluster_density(100.0, 0.01, 0.2, 0.1), 100.0 * 1e-4 / 0.02, 1e-15);
    EXPECT_DOUBLE_EQ(cluster_density(1e6, 1.0, 1.0, 1.0), 1.0);
    EXPECT_NEAR(hairs_crossed(0.5, 0.4, 100.0, 0.2, 0.1), 0.5 * 0.4 * std::sqrt(100.0 / (kPi * 0.02)), 1e-12);
    EXPECT_DOUBLE_EQ(hairs_crossed(0.5, 0.0, 100.0, 0.2, 0.1), 1.0);
    // 1 - exp(-lambda), lambda = 2 r n_total l / (pi r_A r_B), r from rho = n_total r^2 / (r_A r_B).
    const double r = std::sqrt(0.5 * 0.02 / 100.0);
    EXPECT_NEAR(hair_hit_probability(0.5, 0.4, 100.0, 0.2, 0.1), 1.0 - std::exp(-2.0 * r * 100.0 * 0.4 / (kPi * 0.02)),
                1e-12);
    EXPECT_DOUBLE_EQ(hair_hit_probability(0.5, 0.0, 100.0, 0.2, 0.1), 0.0);
    EXPECT_NEAR(hair_hit_probability(1.0, 1.0, 1e6, 0.2, 0.1), 1.0, 1e-12);
    for (const auto& [name, call] : std::initializer_list<std::pair<std::string, std::function<void()>>>{
             {"hair_radius", [] { cluster_density(10.0, -1.0, 1.0, 1.0); }},
             {"ray_length", [] { hairs_crossed(0.5, std::nan(""), 10.0, 1.0, 1.0); }},
             {"ray_length", [] { hair_hit_probability(0.5, -1.0, 10.0, 1.0, 1.0); }},
             {"density", [] { hair_hit_probability(0.0, 1.0, 10.0, 1.0, 1.0); }},
             {"hair_count", [] { AggregatedBcsdf(brown(), {0.5, 0.5}, brown_table()); }},
             {"density", [] { AggregatedBcsdf(brown(), {2.0, 0.0}, brown_table()); }}}) {
        try {
            call();
            FAIL() << name;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    }
}

TEST(Aggregated, MaxHairsCrossedIsTheLongestChordOfTheDensestPoint) {
    // Two hairs of 3 control points: n = rho 2 r_A sqrt(n_total / (pi r_A r_B)), capped by n_total.
    const std::vector<float> n_total{40.0f, 9.0f};
    const std::vector<glm::vec2> radii{{1.0f, 0.5f}, {3.0f, 0.01f}, {1.0f, 1.0f}, {3.0f, 0.1f}, {0.0f, 0.0f}, {1.0f, 1.0f}};
    const std::vector<float> density{0.5f, 1.0f, 2.0f, 1.0f, 0.3f, 0.0f};
    double expected = 1.0;
    for (size_t i = 0; i < radii.size(); ++i) {
        const double total = n_total[i / 3], rho = std::min(1.0f, density[i]);
        if (radii[i].x > 0.0f && rho > 0.0)
            expected = std::max(expected, std::min(total, hairs_crossed(rho, 2.0 * radii[i].x, total, radii[i].x, radii[i].y)));
        else
            expected = std::max(expected, total);
    }
    EXPECT_DOUBLE_EQ(max_hairs_crossed(n_total, radii, density), expected);
    // The hair with the empty ellipse counts with its whole n_total (9); the wide flat one of the
    // first hair (123 hairs along its chord) reaches its cap of 40.
    EXPECT_DOUBLE_EQ(expected, 40.0);
    EXPECT_DOUBLE_EQ(max_hairs_crossed({}, {}, {}), 1.0);
    EXPECT_THROW(max_hairs_crossed(n_total, radii, std::span<const float>(density).first(5)), Error);
    EXPECT_THROW(max_hairs_crossed(std::vector<float>{1.0f, 2.0f, 3.0f, 4.0f}, radii, density), Error);
}

}  // namespace
}  // namespace hairlod::bcsdf
