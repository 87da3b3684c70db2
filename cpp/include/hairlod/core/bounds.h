#pragma once
// Axis-aligned bounding box of points.
#include <span>

#include <glm/vec3.hpp>

namespace hairlod {

struct Bounds3 {
    glm::vec3 lower{0.0f};
    glm::vec3 upper{0.0f};
    bool empty = true;

    float diagonal() const;
};

Bounds3 bounding_box(std::span<const glm::vec3> points);

}  // namespace hairlod
