#include "hairlod/hairmesh/tangents.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace hairlod {

glm::vec3 unit_or_zero(const glm::vec3& d) {
    const float length_squared = glm::dot(d, d);
    return length_squared > 0.0f && std::isfinite(length_squared) ? d * (1.0f / std::sqrt(length_squared))
                                                                   : glm::vec3(0.0f);
}

namespace {

// Eq. 5 / 6: reflect the neighbour tangent t about the end segment direction q.
glm::vec3 mirrored_end(const glm::vec3& q, const glm::vec3& t) {
    if (q == glm::vec3(0.0f)) return t;
    if (t == glm::vec3(0.0f)) return q;
    return unit_or_zero(2.0f * q * glm::dot(t, q) - t);
}

// Tangents of points[0], points[stride], ... written to tangents at the same indices.
void strided_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents, size_t stride) {
    const size_t last = (points.size() - 1) / stride * stride;
    const glm::vec3 q_first = unit_or_zero(points[stride] - points[0]);
    const glm::vec3 q_last = unit_or_zero(points[last] - points[last - stride]);
    if (last == stride) {
        tangents[0] = tangents[last] = q_first;
        return;
    }
    for (size_t k = stride; k < last; k += stride) tangents[k] = unit_or_zero(points[k + stride] - points[k - stride]);
    tangents[0] = mirrored_end(q_first, tangents[stride]);
    tangents[last] = mirrored_end(q_last, tangents[last - stride]);
}

}  // namespace

void strand_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents) {
    strided_tangents(points, tangents, 1);
}

void coarse_strand_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents) {
    strided_tangents(points, tangents, 2);
    for (size_t k = 1; k + 1 < points.size(); k += 2) tangents[k] = 0.5f * (tangents[k - 1] + tangents[k + 1]);
}

}  // namespace hairlod
