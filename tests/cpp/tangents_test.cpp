#include "hairlod/hairmesh/tangents.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

namespace hairlod {
namespace {

std::vector<glm::vec3> arc(int count) {
    std::vector<glm::vec3> points;
    for (int k = 0; k < count; ++k) {
        const float a = 1.2f * k / (count - 1);
        points.emplace_back(std::cos(a), std::sin(a), 0.1f * k);
    }
    return points;
}

TEST(Tangents, StraightLineTangentsFollowTheLine) {
    const std::vector<glm::vec3> points{{0, 0, 0}, {1, 2, 2}, {2, 4, 4}, {3, 6, 6}};
    std::vector<glm::vec3> tangents(points.size());
    strand_tangents(points, tangents);
    for (const glm::vec3& t : tangents) EXPECT_LT(glm::distance(t, glm::vec3(1, 2, 2) / 3.0f), 1e-6f);
}

// Bhokare 2024 Eq. 5 and 6: the end tangent makes the same angle with the end segment as its neighbour, on the
// other side.
TEST(Tangents, EndTangentsMirrorTheirNeighbours) {
    const std::vector<glm::vec3> points = arc(9);
    std::vector<glm::vec3> t(points.size());
    strand_tangents(points, t);
    const glm::vec3 q_last = glm::normalize(points[8] - points[7]), q_first = glm::normalize(points[1] - points[0]);
    EXPECT_NEAR(glm::dot(t[8], q_last), glm::dot(t[7], q_last), 1e-6f);
    EXPECT_NEAR(glm::dot(t[0], q_first), glm::dot(t[1], q_first), 1e-6f);
    EXPECT_LT(glm::distance(t[8] + t[7], 2.0f * glm::dot(t[7], q_last) * q_last), 1e-5f);
    for (const glm::vec3& tangent : t) EXPECT_NEAR(glm::length(tangent), 1.0f, 1e-5f);
}

TEST(Tangents, CoarseTangentsUseEvenVerticesOnly) {
    const std::vector<glm::vec3> points = arc(9);
    std::vector<glm::vec3> coarse(points.size()), even_tangents(5);
    coarse_strand_tangents(points, coarse);
    const std::vector<glm::vec3> even{points[0], points[2], points[4], points[6], points[8]};
    strand_tangents(even, even_tangents);
    for (size_t k = 0; k < 5; ++k) EXPECT_LT(glm::distance(coarse[2 * k], even_tangents[k]), 1e-6f);
    EXPECT_LT(glm::distance(coarse[3], 0.5f * (even_tangents[1] + even_tangents[2])), 1e-6f);
}

TEST(Tangents, CoincidentPointsGiveFiniteTangents) {
    const std::vector<glm::vec3> same(5, glm::vec3(1, 2, 3));
    std::vector<glm::vec3> t(5);
    strand_tangents(same, t);
    for (const glm::vec3& tangent : t) EXPECT_EQ(tangent, glm::vec3(0.0f));
    const std::vector<glm::vec3> two{{0, 0, 0}, {0, 0, 2}};
    std::vector<glm::vec3> t2(2);
    strand_tangents(two, t2);
    EXPECT_EQ(t2[0], glm::vec3(0, 0, 1));
    EXPECT_EQ(t2[1], glm::vec3(0, 0, 1));
}

// The component-array form used by strand generation must agree with the vec3 form bit for bit,
// across its vector blocks and scalar remainder, repeated and huge points included.
TEST(Tangents, ComponentArraysGiveTheSameTangents) {
    for (int count : {2, 3, 4, 5, 6, 9, 17, 33}) {
        std::vector<glm::vec3> points = arc(count);
        if (count > 4) points[2] = points[3];                     // a repeated point
        if (count > 8) points[6] = glm::vec3(3e19f, 0.0f, 0.0f);  // a squared length beyond float range
        std::vector<float> x, y, z;
        for (const glm::vec3& p : points) {
            x.push_back(p.x);
            y.push_back(p.y);
            z.push_back(p.z);
        }
        std::vector<glm::vec3> expected(points.size()), actual(points.size(), glm::vec3(7.0f));
        strand_tangents(points, expected);
        strand_tangents(x.data(), y.data(), z.data(), actual);
        for (int k = 0; k < count; ++k) EXPECT_EQ(actual[k], expected[k]) << count << " " << k;
    }
}

}  // namespace
}  // namespace hairlod
