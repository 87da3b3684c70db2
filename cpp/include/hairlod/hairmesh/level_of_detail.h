#pragma once
// Strand and vertex level of detail (hair-meshes-realtime.txt Sec. 3.6, Eq. 7-12).
#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

namespace hairlod {

// Bhokare 2024 Eq. 7: L = min(1, alpha h R / (d tan(theta))) for a model of size h at distance d seen with a
// vertical resolution of R pixels and field of view theta in (0, pi/2) radians.
float detail_level(float model_size, float resolution_px, float distance, float field_of_view, float alpha);

// Bhokare 2024 Eq. 8: ceil(L (N + delta)) strands of a bundle of N at level L in (0, 1], delta in [0, 1) its
// random increment; capped at N so that L = 1 yields exactly the requested strands.
int64_t lod_strand_count(int64_t strands, float level, float delta);

// Sec. 3.6.1: radius factor min(1 / L, N) that keeps the amount of hair material.
float thickness_compensation(int64_t strands, float level);

// Bhokare 2024 Eq. 9, 10 and 12 for strands of at most `max_segments` = n s = 2^E segments.
struct VertexLod {
    int exponent = 0;    // e: the strand has 2^e + 1 vertices
    float gamma = 0.0f;  // transition factor towards level e - 1; 0 when not transitioning
};
VertexLod vertex_lod(int max_segments, float level, float transition);

// Bhokare 2024 Eq. 11 and the tangent morph of Sec. 3.6.2: odd vertices move towards the midpoint of their
// neighbours and all tangents towards the coarse tangents, by gamma. `tangents` must hold
// strand_tangents(points) on entry; `coarse` is scratch of the same size. Morphed tangents are the
// paper's blend t' = (1 - gamma) t + gamma t~, of length <= 1 while a transition is under way.
void morph_vertex_lod(std::span<glm::vec3> points, std::span<glm::vec3> tangents, std::span<glm::vec3> coarse,
                      float gamma);

}  // namespace hairlod
