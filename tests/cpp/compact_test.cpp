#include "hairlod/lod/compact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

namespace hairlod {
namespace {

glm::vec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<float> normal(0.0f, 1.0f);
    return glm::normalize(glm::vec3(normal(rng), normal(rng), normal(rng)));
}

TEST(QuantisationBox, DecodesWithinHalfAStepAndHitsTheCorners) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> uniform(-3.0f, 5.0f);
    std::vector<glm::vec3> points(1000);
    for (glm::vec3& p : points) p = {uniform(rng), 0.01f * uniform(rng), 1e5f + uniform(rng)};
    const QuantisationBox box = QuantisationBox::enclosing(points);
    for (const glm::vec3& p : points) {
        const glm::vec3 error = glm::abs(box.decode(box.encode(p)) - p);
        for (int axis = 0; axis < 3; ++axis)
            // Half a step, plus float rounding of lower + step * code at the box's magnitude.
            ASSERT_LE(error[axis], 0.5f * box.step[axis] + 2e-7f * std::abs(p[axis])) << "axis " << axis;
    }
    const glm::u16vec3 top = box.encode(box.lower + 65535.0f * box.step);
    EXPECT_EQ(top, glm::u16vec3(65535));
    EXPECT_EQ(box.encode(box.lower - glm::vec3(1.0f)), glm::u16vec3(0));  // outside: clamped
}

TEST(QuantisationBox, FlatBoxesDecodeExactly) {
    const std::vector<glm::vec3> points(3, glm::vec3(1.5f, -2.0f, 0.25f));
    const QuantisationBox box = QuantisationBox::enclosing(points);
    EXPECT_EQ(box.decode(box.encode(points[0])), points[0]);
}

TEST(Octahedral, AngularErrorBelowTheStatedBound) {
    std::mt19937 rng(2);
    std::vector<glm::vec3> units{{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, glm::normalize(glm::vec3(1, 1, -1))};
    for (int i = 0; i < 10000; ++i) units.push_back(random_unit(rng));
    for (const glm::vec3& u : units) {
        const glm::vec3 decoded = decode_octahedral(encode_octahedral(u));
        ASSERT_NEAR(glm::length(decoded), 1.0f, 1e-6f);
        // sin of the angle (acos near 1 is too coarse in float to measure it).
        ASSERT_GT(glm::dot(decoded, u), 0.0f);
        ASSERT_LT(glm::length(glm::cross(decoded, u)), 1e-4f) << u.x << " " << u.y << " " << u.z;
    }
}

TEST(Perpendicular, DecodesPerpendicularAndWithinHalfAStepUpToSign) {
    std::mt19937 rng(3);
    for (int i = 0; i < 10000; ++i) {
        const glm::vec3 axis = i == 0 ? glm::vec3(0, 0, -1) : random_unit(rng);
        const glm::vec3 perpendicular = glm::normalize(glm::cross(axis, random_unit(rng)));
        const glm::vec3 decoded = decode_perpendicular(axis, encode_perpendicular(axis, perpendicular));
        ASSERT_NEAR(glm::dot(decoded, axis), 0.0f, 1e-6f);
        ASSERT_NEAR(glm::length(decoded), 1.0f, 1e-6f);
        // pi / 65536 rad steps: at most half a step (2.4e-5 rad) off, plus float rounding.
        ASSERT_LT(glm::length(glm::cross(decoded, perpendicular)), 3e-5f);
    }
}

TEST(HalfUp, NeverBelowAndWithinOneHalfUlpAbove) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> log_uniform(-20.0f, 20.0f);
    for (int exponent : {-30, -12, 0, 7}) {
        for (int i = 0; i < 10000; ++i) {
            const float value = std::ldexp(std::exp2(log_uniform(rng)), exponent);
            const float scaled = std::ldexp(value, -exponent);
            if (scaled < std::exp2(-14.0f) || scaled > 60000.0f) continue;  // outside the half's normal range
            const float decoded = decode_half(encode_half_up(value, exponent), exponent);
            ASSERT_GE(decoded, value);
            ASSERT_LE(decoded, value * (1.0f + std::exp2(-10.0f)));
        }
    }
    EXPECT_EQ(decode_half(encode_half_up(0.0f, 3), 3), 0.0f);
    EXPECT_EQ(decode_half(encode_half_up(0.75f, -2), -2), 0.75f);  // exact values stay exact
}

}  // namespace
}  // namespace hairlod
