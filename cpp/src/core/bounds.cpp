#include "hairlod/core/bounds.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

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

}  // namespace hairlod
