#pragma once
// The skinning weights of one L0 cluster at one control point: its map as a fixed linear combination
// of deformed guide points (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 4, "computing interpolation
// weights", made second-order accurate).
//
// The paper interpolates inside the triangular prism of a cluster's 3 guides. That is exact for
// rigid motions, but under a non-rigid one (a bending neck) the error grows with the square of the
// distance between guides, and a strand outside its guides' triangle is extrapolated linearly: on
// 100000 strands and 256 guides a 0.4 rad bend left the strands 29 radii off at the 99th
// percentile and 283 at worst. Here, per cluster and control point k, a quadratic field q(p)
// (10 monomials per coordinate) is fitted by weighted least squares to the nearest kStencilGuides
// guides' points at k - 1, k and k + 1, Gaussian-weighted around the cluster's strand points; a
// ridge pulls it towards the prism frame's own affine map, which so decides what the guides leave
// open (a single straight guide, coplanar roots) and keeps rigid motions exact. Every rest point of
// the cluster at k moves by that field, evaluated at the point: the best single affine map per
// cluster and control point (the field's least-squares projection, which an earlier version used)
// left the same bend 2.7 radii off at the 99th percentile, the field itself about 0.5.
// The fit is linear in the deformed guide points and in the prism map, so everything but one
// weighted sum per frame is computed once from the rest pose.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "hairlod/lod/guide_frame.h"

namespace hairlod {

struct LodAsset;

// Guides whose points enter one stencil (fewer when the asset has fewer). On the bend of `bench
// skinning` (20k / 100k strands, the affine projection of the field) 8 gave p99 4.67 / 2.70 strand
// radii, 6 gave 4.84 / 2.75 (too few to pin the 10 monomials everywhere) and 12 gave 4.69 / 2.72
// (reaching farther, fitting worse).
inline constexpr int kStencilGuides = 8;

// The field's monomials of the scaled offset x = (p - centroid) / scale:
// 1, x, y, z, x^2, y^2, z^2, xy, yz, zx.
inline constexpr int kFieldMonomials = 10;
// float, as the terms' weights: the prior's sum joins theirs in the same vector lanes.
using FieldWeights = std::array<float, kFieldMonomials>;

struct StencilTerm {
    int32_t point = 0;  // index into the guides' control points [guides * n_c]
    // Its share of each monomial's coefficient (see QuadraticStencil). float: the per-frame sum
    // vectorises twice as wide as in double (3.4 against 4.4 ms a frame for 100k strands) and
    // moves the bend's points by under 1e-3 strand radii.
    std::array<float, kFieldMonomials> weight{};
};

// The field of one cluster and control point: a rest point p goes to
//   reference' + sum_m C_m b_m((p - centroid) / scale),
// C_m = sum over terms of (d_point - reference') weight_m + c0 prior[0]_m + sum_i (M e_i) prior[1 + i]_m,
// with d the deformed guide points, reference' = d_reference, M the prism frame's map (frame_map)
// and c0 = deformed frame origin - reference' + M (centroid - rest frame origin).
struct QuadraticStencil {
    glm::dvec3 centroid{0.0};  // rest centroid of the cluster's strand points at k
    double scale = 1.0;        // the field's length scale: its guides' reach
    int32_t reference = 0;     // the guide point translations are measured from (the nearest guide's)
    int32_t first_term = 0, term_count = 0;
    FieldWeights prior[4];     // the prism map's share (as above)
};

struct SkinningStencils {
    std::vector<QuadraticStencil> stencils;  // [clusters * n_c]
    std::vector<StencilTerm> terms;
};

// The stencils of every L0 cluster and control point, from the asset's rest pose; `rest_frames`
// are the prism frames at rest ([clusters * n_c], rest_frames in skinning.h).
SkinningStencils skinning_stencils(const LodAsset& asset, std::span<const GuideFrame> rest_frames);

// A quadratic map of rest offsets d (from an anchor) to deformed points:
//   p' = origin + linear d + sum_m quadratic[m] q_m(d), q = (dx^2, dy^2, dz^2, dx dy, dy dz, dz dx).
struct QuadraticMap {
    glm::dvec3 origin{0.0};
    glm::dmat3 linear{1.0};
    std::array<glm::dvec3, 6> quadratic{};
};

// Evaluates stencil i for `deformed_guides` ([guides * n_c]) given the prism frame at rest and
// deformed there, and the prism map between them, as a map of offsets from `anchor` (a rest point).
QuadraticMap stencil_map(const SkinningStencils& stencils, size_t i, std::span<const glm::vec3> deformed_guides,
                         const GuideFrame& rest_frame, const GuideFrame& deformed_frame, const glm::mat3& prism_map,
                         const glm::dvec3& anchor);

}  // namespace hairlod
