#include "hairlod/io/read_options.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "hairlod/core/error.h"

namespace hairlod::io {
namespace {

TEST(ReadOptions, GivenRadiusIsUsed) {
    const std::vector<glm::vec3> points{{0, 0, 0}, {3, 4, 0}};
    EXPECT_EQ(resolve_default_radius({0.25f}, points), 0.25f);
    EXPECT_EQ(resolve_default_radius({0.0f}, points), 0.0f);
}

TEST(ReadOptions, FallbackIsAFractionOfTheBoundingBoxDiagonal) {
    const std::vector<glm::vec3> points{{0, 0, 0}, {3, 4, 0}};
    EXPECT_FLOAT_EQ(resolve_default_radius({}, points), 5.0f * default_radius_per_diagonal);
    EXPECT_EQ(resolve_default_radius({}, std::vector<glm::vec3>{}), 0.0f);
}

TEST(ReadOptions, RejectsNegativeOrNonFiniteRadius) {
    const std::vector<glm::vec3> points{{0, 0, 0}};
    EXPECT_THROW(resolve_default_radius({-1.0f}, points), Error);
    EXPECT_THROW(resolve_default_radius({std::numeric_limits<float>::quiet_NaN()}, points), Error);
    EXPECT_THROW(resolve_default_radius({std::numeric_limits<float>::infinity()}, points), Error);
}

TEST(ReadOptions, NonFinitePointsGiveAFiniteFallback) {
    const std::vector<glm::vec3> points{{0, 0, 0}, {std::numeric_limits<float>::infinity(), 0, 0}};
    EXPECT_TRUE(std::isfinite(resolve_default_radius({}, points)));
}

}  // namespace
}  // namespace hairlod::io
