#pragma once
// Whole-set measurements: bounding box and per-curve polyline lengths.
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "hairlod/core/strand_set.h"

namespace hairlod {

struct Bounds3 {
    glm::vec3 lower{0.0f};
    glm::vec3 upper{0.0f};
    bool empty = true;

    float diagonal() const;
};

Bounds3 bounding_box(std::span<const glm::vec3> points);

// Length of each curve's control polyline, accumulated in double.
std::vector<double> curve_lengths(const StrandSet& strands);

}  // namespace hairlod
