#pragma once
// Strand vertex tangents (hair-meshes-realtime.txt Sec. 3.5, Eq. 5-6).
#include <span>

#include <glm/vec3.hpp>

namespace hairlod {

// d / |d|, or the zero vector where d has no (finite) length.
glm::vec3 unit_or_zero(const glm::vec3& d);

// Unit tangents of a polyline of at least 2 points: central differences p_{k+1} - p_{k-1} inside;
// the end tangents mirror their neighbour's tangent about the end segment (Eq. 5 and 6), so the
// ends shade consistently when vertex LoD changes the vertex count. With 2 points both tangents are
// the segment direction. Where the strand has no length a tangent is the zero vector.
void strand_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents);

// The same for the even-indexed points only (the vertices kept by the next coarser vertex LoD);
// odd tangents are the mean of their even neighbours (Sec. 3.6.2). Needs an odd point count >= 3.
void coarse_strand_tangents(std::span<const glm::vec3> points, std::span<glm::vec3> tangents);

}  // namespace hairlod
