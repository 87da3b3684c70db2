#pragma once
// The skinning weights of one L0 cluster at one control point: its affine map as a fixed linear
// combination of deformed guide points (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 4, "computing
// interpolation weights", made second-order accurate).
//
// The paper interpolates inside the triangular prism of a cluster's 3 guides. That is exact for
// rigid motions, but under a non-rigid one (a bending neck) the error grows with the square of the
// distance between guides, and a strand outside its guides' triangle is extrapolated linearly: on
// 20000 strands and 156 guides a 0.4 rad bend left the strands 42 radii off at the 99th percentile
// and 778 at worst. Here, per cluster and control point k:
//  1. a quadratic field q(p) (10 monomials per coordinate) is fitted by weighted least squares to
//     the nearest kStencilGuides guides' points at k - 1, k and k + 1, Gaussian-weighted around the
//     cluster; a ridge pulls it towards the prism frame's own affine map, which so decides what the
//     guides leave open (a single straight guide, coplanar roots) and keeps rigid motions exact;
//  2. of that field, the affine map closest over the cluster's rest strand points at k is kept
//     (least squares; a faint stencil of points around their centroid settles directions in which
//     they do not spread), because a renderer applies one affine map per cluster and control point.
// Both steps are linear in the deformed guide points and in the prism map, so everything but one
// weighted sum per frame is computed once from the rest pose.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "hairlod/lod/guide_frame.h"

namespace hairlod {

struct LodAsset;

// Guides whose points enter one stencil (fewer when the asset has fewer). On the bend of `bench
// skinning` (20k / 100k strands) 8 gave p99 4.67 / 2.70 strand radii, 6 gave 4.84 / 2.75 (too few
// to pin the 10 monomials everywhere) and 12 gave 4.69 / 2.72 (reaching farther, fitting worse).
inline constexpr int kStencilGuides = 8;

struct StencilTerm {
    int32_t point = 0;        // index into the guides' control points [guides * n_c]
    glm::dvec4 weight{0.0};   // its share of the columns of [A | t] (see AffineStencil)
};

// The map of one cluster and control point: a rest point p goes to
//   reference' + t + A (p - centroid),
// [A | t] = sum over terms of (d_point - reference') weight^T + c0 prior[0]^T + sum_i (M e_i) prior[1 + i]^T,
// with d the deformed guide points, reference' = d_reference, M the prism frame's map (frame_map)
// and c0 = deformed frame origin - reference' + M (centroid - rest frame origin).
struct AffineStencil {
    glm::dvec3 centroid{0.0};  // rest centroid of the cluster's strand points at k
    int32_t reference = 0;     // the guide point translations are measured from (the nearest guide's)
    int32_t first_term = 0, term_count = 0;
    glm::dvec4 prior[4];       // the prism map's share (rows as above)
};

struct SkinningStencils {
    std::vector<AffineStencil> stencils;  // [clusters * n_c]
    std::vector<StencilTerm> terms;
};

// The stencils of every L0 cluster and control point, from the asset's rest pose; `rest_frames`
// are the prism frames at rest ([clusters * n_c], rest_frames in skinning.h).
SkinningStencils skinning_stencils(const LodAsset& asset, std::span<const GuideFrame> rest_frames);

// The affine map of stencil i: p' = centroid_image + linear * (p - stencil.centroid).
struct StencilMap {
    glm::dvec3 centroid_image{0.0};
    glm::dmat3 linear{1.0};
};

// Evaluates stencil i for `deformed_guides` ([guides * n_c]) given the prism frame at rest and
// deformed there, and the prism map between them.
StencilMap stencil_map(const SkinningStencils& stencils, size_t i, std::span<const glm::vec3> deformed_guides,
                       const GuideFrame& rest_frame, const GuideFrame& deformed_frame, const glm::mat3& prism_map);

}  // namespace hairlod
