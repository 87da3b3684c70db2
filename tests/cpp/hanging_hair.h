#pragma once
// Test input shared by the selection tests: strands hanging from the upper part of a unit sphere,
// `points` points each, radius 0.002, deterministic for `seed`.
#include <cmath>
#include <random>
#include <vector>

#include "hairlod/core/strand_set.h"

namespace hairlod::testing {

inline StrandSet hanging_hair(size_t curves, size_t points, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    StrandSet strands;
    std::vector<glm::vec3> curve(points);
    std::vector<float> radius(points, 0.002f);
    for (size_t c = 0; c < curves; ++c) {
        const float azimuth = 6.2831853f * unit(rng), polar = 1.4f * unit(rng);
        const glm::vec3 root(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar));
        for (size_t i = 0; i < points; ++i) curve[i] = root * (1.0f + 0.02f * i) + glm::vec3(0, 0, -0.1f * i);
        strands.add_curve(curve, radius);
    }
    return strands;
}

}  // namespace hairlod::testing
