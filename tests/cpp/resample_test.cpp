#include "hairlod/curves/resample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

StrandSet single_curve(std::vector<glm::vec3> points, std::vector<float> radius = {}) {
    const std::vector<int64_t> counts{static_cast<int64_t>(points.size())};
    return strands_from_counts(std::move(points), counts, std::move(radius));
}

TEST(Resample, StraightLineBecomesEvenlySpaced) {
    const StrandSet line = single_curve({{0, 0, 0}, {0.1f, 0, 0}, {0.3f, 0, 0}, {1, 0, 0}});
    const StrandSet result = resample_strands(line, {.points_per_curve = 11});
    ASSERT_EQ(result.point_count(), 11u);
    for (int i = 0; i < 11; ++i) {
        EXPECT_NEAR(result.points[i].x, i / 10.0f, 2e-3f) << i;
        EXPECT_NEAR(result.points[i].y, 0.0f, 1e-6f);
    }
}

TEST(Resample, EndsAreExact) {
    const StrandSet curve = single_curve({{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, 2}});
    const StrandSet result = resample_strands(curve, {.points_per_curve = 7});
    EXPECT_EQ(result.points.front(), curve.points.front());
    EXPECT_EQ(result.points.back(), curve.points.back());
}

TEST(Resample, CircleArcStaysOnCircleWithEqualSpacing) {
    std::vector<glm::vec3> arc;
    for (int i = 0; i <= 8; ++i) {
        const float angle = static_cast<float>(std::numbers::pi / 2 * i / 8.0);
        arc.emplace_back(std::cos(angle), std::sin(angle), 0.0f);
    }
    const StrandSet result = resample_strands(single_curve(arc), {.points_per_curve = 32});
    const float expected_step = glm::distance(result.points[0], result.points[1]);
    for (size_t i = 0; i < result.point_count(); ++i) {
        // The end segments bend towards their reflected neighbours; inner segments hug the circle.
        const bool inner = i >= 4 && i + 4 < result.point_count();
        EXPECT_NEAR(glm::length(result.points[i]), 1.0f, inner ? 1e-3f : 5e-3f) << i;
        if (i > 0) {
            EXPECT_NEAR(glm::distance(result.points[i - 1], result.points[i]), expected_step,
                        0.01f * expected_step);
        }
    }
}

TEST(Resample, CoincidentPointsChangeNothing) {
    const glm::vec3 a{0, 0, 0}, b{1, 1, 0}, c{2, 0, 1};
    const StrandSet clean = resample_strands(single_curve({a, b, c}), {.points_per_curve = 9});
    const StrandSet doubled = resample_strands(single_curve({a, a, b, b, b, c}), {.points_per_curve = 9});
    for (size_t i = 0; i < clean.point_count(); ++i)
        EXPECT_NEAR(glm::distance(clean.points[i], doubled.points[i]), 0.0f, 1e-5f) << i;
}

TEST(Resample, CollapsedCurveGivesCopiesOfItsPoint) {
    const glm::vec3 a{3, 2, 1};
    const StrandSet result = resample_strands(single_curve({a, a, a}, {0.5f, 0.5f, 0.5f}), {.points_per_curve = 4});
    for (const glm::vec3& p : result.points) EXPECT_EQ(p, a);
    for (float r : result.radius) EXPECT_EQ(r, 0.5f);
}

TEST(Resample, InterpolatesRadiusAndAttributes) {
    StrandSet line = single_curve({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {0.0f, 1.0f, 2.0f});
    line.set_attribute("temperature", AttributeDomain::Point, 2, {0, 10, 1, 11, 2, 12});
    line.set_attribute("id", AttributeDomain::Curve, 1, {42.0f});
    const StrandSet result = resample_strands(line, {.points_per_curve = 5});
    const std::vector<float>& temperature = result.find_attribute("temperature")->values;
    for (int i = 0; i < 5; ++i) {
        const float expected = i * 0.5f;
        EXPECT_NEAR(result.radius[i], expected, 1e-5f);
        EXPECT_NEAR(temperature[2 * i], expected, 1e-5f);
        EXPECT_NEAR(temperature[2 * i + 1], 10.0f + expected, 1e-5f);
    }
    EXPECT_EQ(result.find_attribute("id")->values, std::vector<float>{42.0f});
    EXPECT_NO_THROW(result.validate());
}

TEST(Resample, ManyCurvesKeepTheirOrder) {
    StrandSet strands;
    for (int c = 0; c < 1000; ++c) {
        const std::vector<glm::vec3> curve{{float(c), 0, 0}, {float(c), 0, 1}, {float(c), 1, 2}};
        strands.add_curve(curve);
    }
    const StrandSet result = resample_strands(strands, {.points_per_curve = 6});
    ASSERT_EQ(result.curve_count(), 1000u);
    for (size_t c = 0; c < 1000; ++c) EXPECT_EQ(result.curve_points(c)[3].x, float(c));
}

TEST(Resample, RejectsFewerThanTwoPoints) {
    const StrandSet line = single_curve({{0, 0, 0}, {1, 0, 0}});
    EXPECT_THROW(resample_strands(line, {.points_per_curve = 1}), Error);
}

}  // namespace
}  // namespace hairlod
