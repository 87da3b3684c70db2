#include "hairlod/hairmesh/tangents.h"

#include <cfloat>
#include <cmath>

#include <glm/geometric.hpp>

#include "hairlod/core/float4.h"

namespace hairlod {

namespace {

// Bhokare 2024 Eq. 5 / 6: reflect the neighbour tangent t about the end segment direction q.
glm::vec3 mirrored_end(const glm::vec3& q, const glm::vec3& t) {
    if (q == glm::vec3(0.0f)) return t;
    if (t == glm::vec3(0.0f)) return q;
    return unit_or_zero(2.0f * q * glm::dot(t, q) - t);
}

// The end tangents of Bhokare 2024 Eq. 5 and 6 (or, for a single segment, its direction at both ends) at indices
// 0 and last, from the interior tangents at stride and last - stride.
void end_tangents(const glm::vec3& q_first, const glm::vec3& q_last, std::span<glm::vec3> tangents, size_t last,
                  size_t stride) {
    if (last == stride) {
        tangents[0] = tangents[last] = q_first;
        return;
    }
    tangents[0] = mirrored_end(q_first, tangents[stride]);
    tangents[last] = mirrored_end(q_last, tangents[last - stride]);
}

// Tangents of points[0], points[stride], ... written to tangents at the same indices.
void strided_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents, size_t stride) {
    const size_t last = (points.size() - 1) / stride * stride;
    for (size_t k = stride; k < last; k += stride) tangents[k] = unit_or_zero(points[k + stride] - points[k - stride]);
    end_tangents(unit_or_zero(points[stride] - points[0]), unit_or_zero(points[last] - points[last - stride]), tangents,
                 last, stride);
}

// Interior tangents from component arrays: unit_or_zero of the central differences, four at a
// time (core/float4.h), with a scalar remainder so that nothing is written past the strand.
void interior_tangents(const float* x, const float* y, const float* z, glm::vec3* out, size_t n) {
    size_t k = 1;
    for (; k + 4 < n; k += 4) {
        const Float4 dx = load4(x + k + 1) - load4(x + k - 1), dy = load4(y + k + 1) - load4(y + k - 1),
                     dz = load4(z + k + 1) - load4(z + k - 1);
        const Float4 length_squared = dx * dx + dy * dy + dz * dz;
        const Float4 scale = where4((length_squared > 0.0f) & (length_squared <= FLT_MAX), 1.0f / sqrt4(length_squared));
        store_interleaved4(&out[k].x, dx * scale, dy * scale, dz * scale);
    }
    for (; k + 1 < n; ++k) out[k] = unit_or_zero(glm::vec3(x[k + 1] - x[k - 1], y[k + 1] - y[k - 1], z[k + 1] - z[k - 1]));
}

}  // namespace

void strand_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents) {
    strided_tangents(points, tangents, 1);
}

void coarse_strand_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents) {
    strided_tangents(points, tangents, 2);
    for (size_t k = 1; k + 1 < points.size(); k += 2) tangents[k] = 0.5f * (tangents[k - 1] + tangents[k + 1]);
}

void strand_tangents(const float* x, const float* y, const float* z, std::span<glm::vec3> tangents) {
    const size_t n = tangents.size(), last = n - 1;
    interior_tangents(x, y, z, tangents.data(), n);
    const auto at = [&](size_t k) { return glm::vec3(x[k], y[k], z[k]); };
    end_tangents(unit_or_zero(at(1) - at(0)), unit_or_zero(at(last) - at(last - 1)), tangents, last, 1);
}

}  // namespace hairlod
