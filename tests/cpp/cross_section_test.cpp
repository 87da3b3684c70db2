#include "hairlod/lod/cross_section.h"

#include <gtest/gtest.h>

#include <random>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

const glm::vec3 kAlongZ(0, 0, 1);

CrossSection fit(const std::vector<glm::vec3>& points, float radius, float coverage = 0.95f) {
    std::vector<float> scratch;
    return fit_cross_section(points, std::vector<glm::vec3>(points.size(), kAlongZ), radius, coverage, scratch);
}

TEST(CrossSection, AnisotropicSpreadCoversTheRequestedFraction) {
    std::mt19937 rng(1);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    std::vector<glm::vec3> points;
    for (int i = 0; i < 400; ++i) points.push_back({3.0f * normal(rng), 0.5f * normal(rng), 0.1f * normal(rng)});
    const CrossSection s = fit(points, 0.0f);
    EXPECT_NEAR(std::abs(s.major_axis.x), 1.0f, 0.02f);
    EXPECT_NEAR(std::abs(s.minor_axis.y), 1.0f, 0.02f);
    EXPECT_GT(s.major_radius / s.minor_radius, 4.0f);
    int inside = 0;
    for (const auto& p : points) inside += inside_ellipse(s, p);
    EXPECT_EQ(inside, s.covered);
    EXPECT_GE(inside, 380);  // 95% of 400
    EXPECT_LE(inside, 385);  // the quantile, not everything
}

TEST(CrossSection, GrowthToCoverIsTheQuantileOfEllipticalDistances) {
    CrossSection unit;  // radius 1 about the origin in the xy plane
    unit.major_radius = unit.minor_radius = 1.0f;
    const std::vector<glm::vec3> points{{0.5f, 0, 0}, {0, 2, 0}, {3, 0, 7}, {0, 0, -4}};
    std::vector<float> scratch;
    EXPECT_NEAR(growth_to_cover(unit, points, 2, scratch), 1.0, 2e-5);  // two inside already: no growth
    EXPECT_NEAR(growth_to_cover(unit, points, 3, scratch), 2.0, 1e-4);
    EXPECT_NEAR(growth_to_cover(unit, points, 4, scratch), 3.0, 1e-4);
    CrossSection grown = unit;
    grown.major_radius = grown.minor_radius = static_cast<float>(growth_to_cover(unit, points, 4, scratch));
    for (const glm::vec3& p : points) EXPECT_TRUE(inside_ellipse(grown, p));
}

TEST(CrossSection, SingleMemberHasTheStrandRadius) {
    const CrossSection s = fit({glm::vec3(1, 2, 3)}, 0.01f);
    EXPECT_NEAR(s.major_radius, 0.01f, 1e-6f);
    EXPECT_NEAR(s.minor_radius, 0.01f, 1e-6f);
    EXPECT_EQ(s.covered, 1);
    EXPECT_NEAR(glm::dot(s.major_axis, kAlongZ), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(s.minor_axis, kAlongZ), 0.0f, 1e-6f);
}

TEST(CrossSection, CoincidentAndCollinearMembersAreCovered) {
    const CrossSection coincident = fit(std::vector<glm::vec3>(10, glm::vec3(5, 5, 5)), 0.0f);
    EXPECT_EQ(coincident.covered, 10);
    EXPECT_TRUE(std::isfinite(coincident.major_radius));
    std::vector<glm::vec3> line;
    for (int i = 0; i < 20; ++i) line.push_back({0.1f * i, 0.1f * i, 0});
    const CrossSection collinear = fit(line, 0.001f, 1.0f);
    EXPECT_EQ(collinear.covered, 20);
    EXPECT_NEAR(std::abs(glm::dot(collinear.major_axis, glm::normalize(glm::vec3(1, 1, 0)))), 1.0f, 1e-5f);
    // The minor radius is the strand radius scaled like the major axis to cover every point.
    EXPECT_GE(collinear.minor_radius, 0.001f);
    EXPECT_LT(collinear.minor_radius, 0.002f);
}

TEST(CrossSection, HugeCoordinatesStayFinite) {
    std::vector<glm::vec3> points;
    for (int i = 0; i < 30; ++i) points.push_back(glm::vec3(1e5f, -1e5f, 1e5f) + glm::vec3(i % 5, i / 5, 0));
    const CrossSection s = fit(points, 0.0f);
    EXPECT_TRUE(std::isfinite(s.major_radius) && std::isfinite(s.minor_radius));
    EXPECT_GE(s.covered, 29);
}

TEST(CrossSection, RejectsMismatchedInput) {
    std::vector<float> scratch;
    EXPECT_THROW(fit_cross_section({}, {}, 0.0f, 0.95f, scratch), Error);
}


TEST(CrossSection, StrandCrossesThePlaneWhereItsSegmentMeetsIt) {
    // A straight strand up x = 0.5 from z = -1 to 3 (5 points), the plane through (0, 0, 1) with normal
    // (1, 0, 1) / sqrt 2: they meet at z = 1 - 0.5 = 0.5, on segment 1 (z from 0 to 1), wherever k is.
    const std::vector<glm::vec3> strand = {{0.5f, 0, -1}, {0.5f, 0, 0}, {0.5f, 0, 1}, {0.5f, 0, 2}, {0.5f, 0, 3}};
    const glm::vec3 normal = glm::normalize(glm::vec3(1, 0, 1));
    for (size_t k : {size_t{0}, size_t{2}, size_t{4}}) {
        const glm::vec3 q = strand_plane_crossing(strand, k, {0, 0, 1}, normal);
        EXPECT_NEAR(q.x, 0.5f, 1e-6f);
        EXPECT_NEAR(q.z, 0.5f, 1e-6f);
        EXPECT_NEAR(glm::dot(q - glm::vec3(0, 0, 1), normal), 0.0f, 1e-6f);
    }
}

TEST(CrossSection, StrandCrossingNearestItsPointIsTaken) {
    // A strand zig-zagging across the plane z = 0 crosses it at x = 0.5, 1.5 and 2.5; the crossing nearest
    // its point k is taken (k = 0: the first, k = 3: the last).
    const std::vector<glm::vec3> strand = {{0, 0, -1}, {1, 0, 1}, {2, 0, -1}, {3, 0, 1}};
    EXPECT_NEAR(strand_plane_crossing(strand, 0, {0, 0, 0}, {0, 0, 1}).x, 0.5f, 1e-6f);
    EXPECT_NEAR(strand_plane_crossing(strand, 1, {0, 0, 0}, {0, 0, 1}).x, 0.5f, 1e-6f);  // 0.5 and 1.5 tie: the first
    EXPECT_NEAR(strand_plane_crossing(strand, 3, {0, 0, 0}, {0, 0, 1}).x, 2.5f, 1e-6f);
}

TEST(CrossSection, StrandThatMissesThePlaneIsProjectedOntoIt) {
    // Entirely above the plane z = 0: its point k moved along the normal onto the plane.
    const std::vector<glm::vec3> strand = {{0, 0, 1}, {1, 2, 2}, {2, 0, 3}};
    const glm::vec3 q = strand_plane_crossing(strand, 1, {0, 0, 0}, {0, 0, 1});
    EXPECT_FLOAT_EQ(q.x, 1.0f);
    EXPECT_FLOAT_EQ(q.y, 2.0f);
    EXPECT_FLOAT_EQ(q.z, 0.0f);
    EXPECT_THROW(strand_plane_crossing(strand, 3, {0, 0, 0}, {0, 0, 1}), Error);
}

TEST(CrossSection, SectionDiameterIsTheWidestPairOfProjectedCorners) {
    // Against all six distances between the corners centre +- major, centre +- minor projected onto
    // the plane normal to the tangent, for random (not orthogonal) axes and tangents, grazing included.
    std::mt19937 rng(11);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    auto random_vector = [&] { return glm::vec3(normal(rng), normal(rng), normal(rng)); };
    for (int trial = 0; trial < 2000; ++trial) {
        const glm::vec3 tangent = glm::normalize(random_vector());
        const glm::vec3 major = random_vector() * (trial % 3 == 0 ? 1e-3f : 1.0f);
        // Every fifth minor axis nearly along the tangent: its projection almost vanishes.
        const glm::vec3 minor = trial % 5 == 0 ? 0.7f * tangent + 1e-4f * random_vector() : random_vector();
        const std::array<glm::vec3, 4> corners = {major, -major, minor, -minor};
        float widest = 0.0f;
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) {
                const glm::vec3 d = corners[i] - corners[j];
                widest = std::max(widest, glm::length(d - glm::dot(d, tangent) * tangent));
            }
        ASSERT_NEAR(section_diameter(tangent, major, minor), widest, 1e-5f * widest) << "trial " << trial;
    }
    EXPECT_EQ(section_diameter(kAlongZ, {0, 0, 2}, {0, 0, -1}), 0.0f);  // both axes along the tangent
}

}  // namespace
}  // namespace hairlod
