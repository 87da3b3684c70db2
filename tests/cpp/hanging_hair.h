#pragma once
// Test input shared by the LoD tests: strands hanging from the upper part of a unit sphere, `points`
// points each, radius 0.002, deterministic for `seed`.
#include <cmath>
#include <random>
#include <vector>

#include "hairlod/core/strand_set.h"

namespace hairlod::testing {

// Roots drawn uniformly in azimuth and in polar angle up to 1.4 rad; point i of a curve is
// shape(root, azimuth, i).
template <typename Shape>
StrandSet sphere_hair(size_t curves, size_t points, unsigned seed, Shape shape) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    StrandSet strands;
    std::vector<glm::vec3> curve(points);
    std::vector<float> radius(points, 0.002f);
    for (size_t c = 0; c < curves; ++c) {
        const float azimuth = 6.2831853f * unit(rng), polar = 1.4f * unit(rng);
        const glm::vec3 root(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar));
        for (size_t i = 0; i < points; ++i) curve[i] = shape(root, azimuth, i);
        strands.add_curve(curve, radius);
    }
    return strands;
}

// Straight strands, 0.1 apart in height per point.
inline StrandSet hanging_hair(size_t curves, size_t points, unsigned seed) {
    return sphere_hair(curves, points, seed, [](const glm::vec3& root, float, size_t i) {
        return root * (1.0f + 0.02f * static_cast<float>(i)) + glm::vec3(0, 0, -0.1f * static_cast<float>(i));
    });
}

// Wavy strands one unit long, shifted by `offset`.
inline StrandSet wavy_hair(size_t curves, size_t points, unsigned seed, glm::vec3 offset = glm::vec3(0.0f)) {
    return sphere_hair(curves, points, seed, [&](const glm::vec3& root, float azimuth, size_t i) {
        const float t = static_cast<float>(i) / static_cast<float>(points - 1);
        return offset + root * (1.0f + 0.2f * t) + glm::vec3(0.05f * std::sin(9.0f * t + azimuth), 0.0f, -t);
    });
}

}  // namespace hairlod::testing
