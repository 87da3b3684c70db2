#pragma once
// Strand vertex tangents (hair-meshes-realtime.txt Sec. 3.5, Eq. 5-6).
#include <cmath>
#include <span>

#include <glm/vec3.hpp>

namespace hairlod {

// d / |d|, or the zero vector where d has no (finite) length. Inline: called per generated vertex.
inline glm::vec3 unit_or_zero(const glm::vec3& d) {
    const float length_squared = d.x * d.x + d.y * d.y + d.z * d.z;
    return length_squared > 0.0f && std::isfinite(length_squared) ? d * (1.0f / std::sqrt(length_squared))
                                                                   : glm::vec3(0.0f);
}

// Unit tangents of a polyline of at least 2 points: central differences p_{k+1} - p_{k-1} inside;
// the end tangents mirror their neighbour's tangent about the end segment (Bhokare 2024 Eq. 5 and 6), so the
// ends shade consistently when vertex LoD changes the vertex count. With 2 points both tangents are
// the segment direction. Where the strand has no length a tangent is the zero vector.
void strand_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents);

// The same for tangents.size() >= 2 points stored component by component (x, y, z arrays), as
// strand generation holds them; equal to the above to the last bit, and vectorised.
void strand_tangents(const float* x, const float* y, const float* z, std::span<glm::vec3> tangents);

// The same for the even-indexed points only (the vertices kept by the next coarser vertex LoD);
// odd tangents are the mean of their even neighbours (Sec. 3.6.2). Needs an odd point count >= 3.
void coarse_strand_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents);

}  // namespace hairlod
