#include "hairlod/core/strand_metrics.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace hairlod {

float Bounds3::diagonal() const { return empty ? 0.0f : glm::length(upper - lower); }

Bounds3 bounding_box(std::span<const glm::vec3> points) {
    Bounds3 box;
    if (points.empty()) return box;
    box.lower = box.upper = points.front();
    for (const glm::vec3& p : points) {
        box.lower = glm::min(box.lower, p);
        box.upper = glm::max(box.upper, p);
    }
    box.empty = false;
    return box;
}

std::vector<double> curve_lengths(const StrandSet& strands) {
    std::vector<double> lengths(strands.curve_count());
    tbb::parallel_for(size_t{0}, lengths.size(), [&](size_t c) {
        const std::span<const glm::vec3> curve = strands.curve_points(c);
        double length = 0.0;
        for (size_t i = 1; i < curve.size(); ++i)
            length += glm::length(glm::dvec3(curve[i]) - glm::dvec3(curve[i - 1]));
        lengths[c] = length;
    });
    return lengths;
}

}  // namespace hairlod
