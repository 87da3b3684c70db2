#include "synthetic_strands.h"

#include <cmath>
#include <random>

namespace hairlod::bench {

StrandSet synthetic_strands(size_t curves, size_t points_per_curve) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    StrandSet strands;
    strands.points.reserve(curves * points_per_curve);
    strands.radius.reserve(curves * points_per_curve);
    std::vector<glm::vec3> curve(points_per_curve);
    for (size_t c = 0; c < curves; ++c) {
        const float azimuth = 6.2831853f * unit(rng), height = unit(rng);
        const glm::vec3 root{std::cos(azimuth), std::sin(azimuth), height};
        for (size_t i = 0; i < points_per_curve; ++i) {
            const float t = static_cast<float>(i) / static_cast<float>(points_per_curve - 1);
            curve[i] = root * (1.0f + 0.3f * t) + glm::vec3(0.05f * std::sin(12.0f * t + azimuth), 0.0f, -t);
        }
        strands.add_curve(curve);
    }
    std::fill(strands.radius.begin(), strands.radius.end(), 0.001f);
    return strands;
}

}  // namespace hairlod::bench
