#include "hairlod/core/strand_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hairlod {
namespace {

TEST(StrandMetrics, BoundingBoxOfPoints) {
    const std::vector<glm::vec3> points{{1, -2, 3}, {-4, 5, 0}, {2, 2, 2}};
    const Bounds3 box = bounding_box(points);
    EXPECT_FALSE(box.empty);
    EXPECT_EQ(box.lower, glm::vec3(-4, -2, 0));
    EXPECT_EQ(box.upper, glm::vec3(2, 5, 3));
    EXPECT_FLOAT_EQ(box.diagonal(), std::sqrt(36.0f + 49.0f + 9.0f));
    EXPECT_TRUE(bounding_box({}).empty);
    EXPECT_EQ(bounding_box({}).diagonal(), 0.0f);
}

TEST(StrandMetrics, CurveLengthsOfPolylines) {
    const std::vector<glm::vec3> points{{0, 0, 0}, {3, 4, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 1}};
    const std::vector<int64_t> counts{2, 3};
    const StrandSet strands = strands_from_counts(points, counts, {});
    const std::vector<double> lengths = curve_lengths(strands);
    ASSERT_EQ(lengths.size(), 2u);
    EXPECT_DOUBLE_EQ(lengths[0], 5.0);
    EXPECT_DOUBLE_EQ(lengths[1], 1.0);
}

TEST(StrandMetrics, HugeCoordinatesStayFinite) {
    const std::vector<glm::vec3> points{{1e30f, 0, 0}, {-1e30f, 0, 0}};
    const std::vector<int64_t> counts{2};
    const StrandSet strands = strands_from_counts(points, counts, {});
    EXPECT_DOUBLE_EQ(curve_lengths(strands)[0], 2.0 * double(1e30f));
}

}  // namespace
}  // namespace hairlod
