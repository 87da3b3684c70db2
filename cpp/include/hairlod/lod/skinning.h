#pragma once
// Per-frame linear skinning of an LoD asset to deformed guides (hair-lod-aggregated-bcsdf.txt
// Sec. 5.1 step 4 and Sec. 5.2: "only the guides are simulated", strands and thick hairs follow
// through the weights). Every skinned point of L0 cluster c at control point k moves by one quadratic
// map of its offset d = p - o_ck from the rest frame origin: p' = o'_ck + M_ck d + Q_ck(d), the
// field that the cluster's stencil (quadratic_stencil.h) makes of the deformed guides near it.
// LodAsset::skin applies the maps to everything on the CPU (export, rendering); FrameSkinning
// computes only the maps and what LoD selection reads, for a renderer that applies the maps to
// rest-pose vertex buffers on the GPU: per frame it costs O(clusters x n_c), not O(points).
#include <array>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "hairlod/lod/quadratic_stencil.h"
#include "hairlod/lod/guide_frame.h"
#include "hairlod/lod/lod_asset.h"

namespace hairlod {

// The map of one L0 cluster at one control point: a rest point p (world, rest pose) at offset
// d = p - rest_origin skins to origin + linear d + sum_m quadratic[m] q_m(d), with
// q = (dx^2, dy^2, dz^2, dx dy, dy dz, dz dx); rest vectors there (tangents, cross-section axes) by
// the map's Jacobian at d.
struct ClusterMap {
    glm::vec3 rest_origin{0.0f};
    glm::vec3 origin{0.0f};
    glm::mat3 linear{1.0f};
    std::array<glm::vec3, 6> quadratic{};
};
glm::vec3 map_point(const ClusterMap& map, const glm::vec3& offset);
glm::mat3 map_jacobian(const ClusterMap& map, const glm::vec3& offset);

// What skinning derives once from the rest pose, per L0 cluster and control point [clusters * n_c]:
// the prism frames of the cluster's guides (stored offsets are relative to their origins) and the
// stencils that turn deformed guides into maps.
struct SkinningRest {
    std::vector<GuideFrame> frames;
    SkinningStencils stencils;
};
SkinningRest skinning_rest(const LodAsset& asset);

// The prism frames alone, and the maps that leave every point where it is (the rest pose) anchored
// at them: what the rest pose needs, without the stencils.
std::vector<GuideFrame> rest_frames(const LodAsset& asset);
std::vector<ClusterMap> identity_maps(std::span<const GuideFrame> rest_frames);

// The maps of every L0 cluster and control point [clusters * n_c] for `deformed_guides` ([guides *
// n_c] points, the guides in the order of guide_strands), given the asset's skinning_rest. Throws
// Error when the guides have the wrong size or a coordinate that is not finite.
std::vector<ClusterMap> cluster_maps(const LodAsset& asset, const SkinningRest& rest,
                                     std::span<const glm::vec3> deformed_guides);

// Strands and thick hairs skinned to `deformed_guides` (LodAsset::skin, with rest derived once by
// the caller for a sequence of frames).
LodGeometry skin_geometry(const LodAsset& asset, const SkinningRest& rest, std::span<const glm::vec3> deformed_guides);

// Strands and thick hairs moved by `maps` ([clusters * n_c]).
LodGeometry mapped_geometry(const LodAsset& asset, std::span<const ClusterMap> maps);

// The guides' control points [guides * n_c] from `guide_curves`: the asset's guide strands, in the
// order of guide_strands, as they are now (moved or deformed, any point count), resampled as
// build_lod resamples them (arc length, LodOptions' default subdivisions). Under a rigid motion, or
// a bend that keeps lengths, they are the moved rest_guides. Throws Error unless there is one curve
// per guide.
std::vector<glm::vec3> resample_guides(const LodAsset& asset, const StrandSet& guide_curves);

// A map as a shader reads it, kMapTexels RGBA texels (skinning.glsl):
//   0: (rest_origin, 0)                          d = p - rest_origin
//   1-3: (linear row r, origin r)                p'_r = dot(texel, (d, 1))
//   4-6: (quadratic coefficients of row r of dx^2, dy^2, dz^2, 0)         + dot(texel.xyz, d * d)
//   7-9: (quadratic coefficients of row r of dx dy, dy dz, dz dx, 0)       + dot(texel.xyz, (dx dy, dy dz, dz dx))
inline constexpr int kMapTexels = 10;
using MapTexels = std::array<glm::vec4, kMapTexels>;
MapTexels map_texels(const ClusterMap& map);

class FrameSkinning {
public:
    // Caches the asset's rest frames and, per thick level, L0 cluster and control point, the rest
    // cross-section of the cluster's widest hair there (the hair LoD selection measures). `asset`
    // must outlive this object. Starts at the rest pose.
    explicit FrameSkinning(const LodAsset& asset);

    // Skins to `deformed_guides` (as cluster_maps; the first call derives the stencils). Throws
    // Error on bad guides and keeps the previous frame.
    void update(std::span<const glm::vec3> deformed_guides);

    const LodAsset& asset() const { return *asset_; }
    // [clusters * n_c] maps from rest to deformed positions, as texels.
    const std::vector<MapTexels>& maps() const { return texels_; }

    // What LoD selection reads (Selection's geometry): per thick level the skinned widest hair of
    // each L0 cluster and control point, and per cluster a sphere holding its deformed strands.
    // Strands and per-hair arrays are empty. The widest hair is the rest pose's, and the ellipsoid
    // holding every hair's semi-axes moves by the Jacobian at its centre, its thinnest diameter
    // scaling with the widest hair's: under a rigid motion all stay exact; under a non-rigid one
    // another hair of the cluster may grow wider.
    // The sphere bounds the cluster's quantisation boxes mapped at every control point, so it holds
    // every skinned strand point (plus the widest strand radius) under any deformation.
    const LodGeometry& selection_geometry() const { return geometry_; }

private:
    void set_maps(std::span<const ClusterMap> maps);
    // Cluster c's texels and selection geometry from its n_c maps; `scratch` is reused between calls.
    void set_cluster_maps(size_t c, std::span<const ClusterMap> maps, std::vector<float>& scratch);
    const LodAsset* asset_;
    SkinningRest rest_;
    // Per thick level, L0 cluster and control point, the rest pose of the cluster's widest hair there
    // (its centres at k - 1, k, k + 1, its semi-axis vectors, the ellipsoid holding every hair's
    // semi-axes and that ellipsoid's thinnest diameter over the widest hair's), stored field by
    // field over the control points (skinning.cpp, WidestField): a frame's work on a cluster then
    // runs across its control points in vector lanes.
    std::vector<std::vector<float>> widest_rest_;  // per level [clusters * kWidestFields * n_c]
    std::vector<float> widest_strand_radius_;      // per cluster
    std::vector<MapTexels> texels_;
    LodGeometry geometry_;
};

}  // namespace hairlod
