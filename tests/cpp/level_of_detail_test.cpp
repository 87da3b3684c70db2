#include "hairlod/hairmesh/level_of_detail.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairlod/hairmesh/tangents.h"

namespace hairlod {
namespace {

TEST(LevelOfDetail, DetailLevelEq7) {
    EXPECT_FLOAT_EQ(detail_level(0.1f, 1000.0f, 1000.0f, 0.5f, 1.0f), 0.1f * 1000.0f / (1000.0f * std::tan(0.5f)));
    EXPECT_EQ(detail_level(1.0f, 1000.0f, 1.0f, 0.5f, 1.0f), 1.0f);
    EXPECT_THROW(detail_level(1.0f, 1000.0f, 0.0f, 0.5f, 1.0f), Error);
    EXPECT_THROW(detail_level(1.0f, 1000.0f, 10.0f, 2.0f, 1.0f), Error);
}

TEST(LevelOfDetail, StrandCountEq8) {
    EXPECT_EQ(lod_strand_count(100, 1.0f, 0.7f), 100);
    EXPECT_EQ(lod_strand_count(100, 0.5f, 0.3f), 51);  // ceil(0.5 * 100.3)
    EXPECT_EQ(lod_strand_count(7, 1e-3f, 0.2f), 1);    // at least one strand for L > 0
    EXPECT_EQ(lod_strand_count(0, 0.5f, 0.9f), 0);
    int64_t previous = 0;
    for (int i = 1; i <= 1000; ++i) {
        const int64_t count = lod_strand_count(300, i / 1000.0f, 0.4f);
        EXPECT_GE(count, previous);
        EXPECT_LE(count - previous, 1);  // a small change in L removes at most one strand here
        previous = count;
    }
    EXPECT_THROW(lod_strand_count(10, 0.0f, 0.5f), Error);
}

TEST(LevelOfDetail, ThicknessCompensation) {
    EXPECT_FLOAT_EQ(thickness_compensation(100, 0.25f), 4.0f);
    EXPECT_FLOAT_EQ(thickness_compensation(3, 0.1f), 3.0f);
    EXPECT_FLOAT_EQ(thickness_compensation(100, 1.0f), 1.0f);
}

TEST(LevelOfDetail, VertexExponentEq9AndTransitionEq12) {
    EXPECT_EQ(vertex_lod(32, 1.0f, 0.5f).exponent, 5);
    EXPECT_EQ(vertex_lod(32, 1.0f, 0.5f).gamma, 0.0f);
    EXPECT_EQ(vertex_lod(32, 0.5f, 0.5f).exponent, 4);
    EXPECT_EQ(vertex_lod(32, 1e-3f, 0.5f).exponent, 0);
    // Just above L = 1/2 the strand has 33 vertices, fully morphed to the 17-vertex shape.
    const VertexLod above = vertex_lod(32, 0.5f + 1e-6f, 0.5f);
    EXPECT_EQ(above.exponent, 5);
    EXPECT_NEAR(above.gamma, 1.0f, 1e-4f);
    // Halfway through the window log2(L n s) = 4.25: gamma = 1 - 0.25 / 0.5.
    EXPECT_NEAR(vertex_lod(32, std::exp2(-0.75f), 0.5f).gamma, 0.5f, 1e-5f);
    EXPECT_EQ(vertex_lod(32, std::exp2(-0.25f), 0.5f).gamma, 0.0f);
    EXPECT_THROW(vertex_lod(24, 1.0f, 0.5f), Error);
    EXPECT_THROW(vertex_lod(32, 1.0f, 0.0f), Error);
}

TEST(LevelOfDetail, FullMorphGivesTheCoarseStrand) {
    std::vector<glm::vec3> points;
    for (int k = 0; k < 9; ++k) points.emplace_back(std::cos(0.4f * k), std::sin(0.4f * k), 0.2f * k);
    std::vector<glm::vec3> tangents(9), coarse(9), coarse_expected(9);
    strand_tangents(points, tangents);
    coarse_strand_tangents(points, coarse_expected);
    const std::vector<glm::vec3> original = points;
    morph_vertex_lod(points, tangents, coarse, 1.0f);
    for (size_t k = 0; k < 9; ++k) {
        if (k % 2 == 0) EXPECT_EQ(points[k], original[k]);
        else EXPECT_LT(glm::distance(points[k], 0.5f * (original[k - 1] + original[k + 1])), 1e-6f);
        EXPECT_LT(glm::distance(tangents[k], coarse_expected[k]), 1e-6f);
    }
}

}  // namespace
}  // namespace hairlod
