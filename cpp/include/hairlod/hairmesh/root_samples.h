#pragma once
// Hair root sample sets (hair-meshes-realtime.txt Sec. 3.3): progressive blue-noise 2D points made
// by weighted sample elimination (Yuksel 2015), one family for quad faces and one for triangles.
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

namespace hairlod {

enum class SampleDomain {
    UnitSquare,    // [0, 1]^2
    UnitTriangle,  // xi_s, xi_t >= 0, xi_s + xi_t < 1
};

// `count` points in the domain ordered so that every prefix is blue noise: candidates (5 per sample)
// are eliminated down to `count`, then repeatedly halved with the Poisson radius of the halved
// count; the order is the reverse elimination order. Deterministic for a seed.
std::vector<glm::vec2> progressive_blue_noise(size_t count, SampleDomain domain, uint64_t seed);

// hair-meshes-realtime.txt Sec. 3.3: the map xi -> xi^Delta from the triangular half to the full
// square, so that bilinear interpolation over a triangle with its third vertex duplicated equals
// barycentric interpolation with weights (1 - xi_s - xi_t, xi_s, xi_t). The paper prints
// xi_s^Delta = xi_s (1 - xi_t); bilinear weights s (1 - t) on the second vertex need
// xi_s^Delta = xi_s / (1 - xi_t), which is what this returns (tested against barycentric).
glm::vec2 triangle_to_square(glm::vec2 xi);

// Several independent progressive sets per domain. Bundles draw a set and one of the domain's
// symmetries (8 of the square, 6 of the triangle) from their index, so neighbouring bundles do not
// repeat the same root pattern (the decorrelation Sec. 3.3 suggests).
struct RootSampleSets {
    size_t samples_per_set = 0;
    int set_count = 0;
    uint64_t seed = 0;
    std::vector<glm::vec2> square;    // set-major: set k, sample i at k * samples_per_set + i; or empty
    std::vector<glm::vec2> triangle;  // the same in the triangular half (mapped on use); or empty

    // Root coordinates (s, t) in [0, 1]^2 for strand `index` of a bundle; bilinear over FaceCorners.
    glm::vec2 root_coordinates(uint64_t bundle, size_t index, bool triangle_face) const;
};

// Builds the square family, the triangle family, or both (a mesh without triangles needs no
// triangle sets); a face whose family was not built must not ask for roots.
RootSampleSets make_root_sample_sets(size_t samples_per_set, int set_count, uint64_t seed, bool squares = true,
                                     bool triangles = true);

}  // namespace hairlod
