#include "hairlod/lod/skinning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hairlod/core/error.h"
#include "hairlod/core/vector_clones.h"
#include "hairlod/curves/resample.h"
#include "hairlod/lod/compact.h"
#include "hairlod/lod/cross_section.h"

namespace hairlod {

namespace {

glm::vec3 unit_or_zero(const glm::vec3& v) {
    const float length = glm::length(v);
    return length > 0.0f ? v / length : glm::vec3(0.0f);
}

// A hair's two semi-axes projected onto the plane normal to its unit `tangent` (as Sec. 5.2
// projects its corners), appended to `out`: what width_ellipsoid must hold.
void append_projected_semi_axes(const glm::vec3& tangent, const glm::vec3& major, const glm::vec3& minor,
                                std::vector<glm::vec3>& out) {
    out.push_back(major - glm::dot(major, tangent) * tangent);
    out.push_back(minor - glm::dot(minor, tangent) * tangent);
}

// A cluster's n_c maps field by field over the control points (MapField x n_c floats), and the rest
// pose of its widest hairs the same way (WidestField x n_c): the layouts the lane kernel reads.
enum MapField : size_t {
    kRestOrigin = 0,   // 3
    kOrigin = 3,       // 3
    kLinear = 6,       // 9, column-major as glm: linear[col][row] at kLinear + 3 col + row
    kQuadratic = 15,   // 18: quadratic[m][row] at kQuadratic + 3 m + row
    kMapFields = 33
};
enum WidestField : size_t {
    kBefore = 0, kCentre = 3, kAfter = 6,  // rest centres at k - 1, k, k + 1 (clamped)
    kMajor = 9, kMinor = 12,                // rest semi-axis vectors at k
    kAxes = 15,                             // 9: the width ellipsoid's axes at rest, axis a at kAxes + 3 a
    kThinnestFraction = 24,                 // its thinnest diameter over the widest hair's diameter
    kWidestFields = 25
};
// What the lane kernel writes per control point: the skinned centre, the square of the widest hair's
// half-width (section_diameter / 2) and the ellipsoid's entries, field by field over at most
// kLaneChunk lanes. A fixed stride tells the compiler that the fields' stores never overlap (with
// n_c as the stride it would test each pair at run time, and gives up past 10 such tests).
enum SelectionField : size_t { kOutCentre = 0, kOutSquaredRadius = 3, kOutEntries = 4, kSelectionFields = 10 };
constexpr size_t kLaneChunk = 16;

// A cluster's n_c maps in MapField layout over n_c + 2 lanes: lane k + 1 holds the map at control
// point k, and lanes 0 and n_c + 1 repeat the first and last maps, so that lanes k, k + 1, k + 2 are
// the maps before, at and after k, clamped at the ends as the tangent's neighbouring centres are.
void put_padded_maps(std::span<const ClusterMap> maps, float* lanes) {
    const size_t stride = maps.size() + 2;
    for (size_t lane_index = 0; lane_index < stride; ++lane_index) {
        const ClusterMap& map = maps[std::clamp(lane_index, size_t{1}, maps.size()) - 1];
        for (int r = 0; r < 3; ++r) {
            lanes[(kRestOrigin + r) * stride + lane_index] = map.rest_origin[r];
            lanes[(kOrigin + r) * stride + lane_index] = map.origin[r];
            for (int col = 0; col < 3; ++col) lanes[(kLinear + 3 * col + r) * stride + lane_index] = map.linear[col][r];
            for (int m = 0; m < 6; ++m) lanes[(kQuadratic + 3 * m + r) * stride + lane_index] = map.quadratic[m][r];
        }
    }
}

// Field `field` of lane p (a pointer to the lane's entry of field 0) in a field-by-field layout of
// n_c lanes.
[[gnu::always_inline]] inline float lane(const float* p, size_t nc, size_t field) { return p[field * nc]; }

struct LaneVector {
    float x, y, z;
};

// map_point of the map in lane `map` (MapField layout) at the rest point p.
[[gnu::always_inline]] inline LaneVector lane_map_point(const float* map, size_t nc, float px, float py, float pz) {
    const float dx = px - lane(map, nc, kRestOrigin), dy = py - lane(map, nc, kRestOrigin + 1),
                dz = pz - lane(map, nc, kRestOrigin + 2);
    const float xx = dx * dx, yy = dy * dy, zz = dz * dz, xy = dx * dy, yz = dy * dz, zx = dz * dx;
    float out[3];
    for (size_t r = 0; r < 3; ++r)
        out[r] = lane(map, nc, kOrigin + r) + lane(map, nc, kLinear + r) * dx + lane(map, nc, kLinear + 3 + r) * dy +
                 lane(map, nc, kLinear + 6 + r) * dz + lane(map, nc, kQuadratic + r) * xx +
                 lane(map, nc, kQuadratic + 3 + r) * yy + lane(map, nc, kQuadratic + 6 + r) * zz +
                 lane(map, nc, kQuadratic + 9 + r) * xy + lane(map, nc, kQuadratic + 12 + r) * yz +
                 lane(map, nc, kQuadratic + 15 + r) * zx;
    return {out[0], out[1], out[2]};
}

// Row `row` of the Jacobian (map_jacobian) of the map in lane `map` at offset d from its rest origin.
[[gnu::always_inline]] inline LaneVector lane_jacobian_row(const float* map, size_t nc, size_t row, float dx, float dy, float dz) {
    const float q0 = lane(map, nc, kQuadratic + row), q1 = lane(map, nc, kQuadratic + 3 + row);
    const float q2 = lane(map, nc, kQuadratic + 6 + row), q3 = lane(map, nc, kQuadratic + 9 + row);
    const float q4 = lane(map, nc, kQuadratic + 12 + row), q5 = lane(map, nc, kQuadratic + 15 + row);
    return {lane(map, nc, kLinear + row) + (2.0f * dx * q0 + dy * q3 + dz * q5),
            lane(map, nc, kLinear + 3 + row) + (2.0f * dy * q1 + dx * q3 + dz * q4),
            lane(map, nc, kLinear + 6 + row) + (2.0f * dz * q2 + dy * q4 + dx * q5)};
}

[[gnu::always_inline]] inline float dot(const LaneVector& a, float x, float y, float z) { return a.x * x + a.y * y + a.z * z; }

// The rest vector in field `field` of lane `rest` times the Jacobian with rows jx, jy, jz.
[[gnu::always_inline]] inline LaneVector lane_apply(const LaneVector& jx, const LaneVector& jy, const LaneVector& jz,
                                                    const float* rest, size_t nc, size_t field) {
    const float x = lane(rest, nc, field), y = lane(rest, nc, field + 1), z = lane(rest, nc, field + 2);
    return {dot(jx, x, y, z), dot(jy, x, y, z), dot(jz, x, y, z)};
}

// The selection geometry of one level's widest hairs of a cluster, lane k being control point
// first + k for k < count <= kLaneChunk: `maps` points at the map of control point first - 1 in a
// MapField layout of map_stride lanes whose lanes k - 1, k, k + 1 hold the maps at the control
// points before, at and after k (put_padded_maps); `rest` at lane `first` of the widest hairs
// (WidestField layout, n_c lanes); `out` receives SelectionField x kLaneChunk floats. The same sums as map_point, map_jacobian, section_diameter (but its square root), mapped
// and symmetric_entries, one lane per control point. No lambdas and no branches: GCC vectorises the
// loop only so (a lambda's captures, a branch or a call each kept it scalar).
HAIRLOD_VECTOR_CLONES void widest_hair_lanes(const float* __restrict maps, size_t map_stride, const float* __restrict rest,
                                             size_t nc, size_t count, float* __restrict out) {
    for (size_t k = 0; k < count; ++k) {
        const float* r = rest + k;
        const float* m = maps + k + 1;
        const float cx = lane(r, nc, kCentre), cy = lane(r, nc, kCentre + 1), cz = lane(r, nc, kCentre + 2);
        const LaneVector centre = lane_map_point(m, map_stride, cx, cy, cz);
        const LaneVector p_before = lane_map_point(m - 1, map_stride, lane(r, nc, kBefore), lane(r, nc, kBefore + 1), lane(r, nc, kBefore + 2));
        const LaneVector p_after = lane_map_point(m + 1, map_stride, lane(r, nc, kAfter), lane(r, nc, kAfter + 1), lane(r, nc, kAfter + 2));
        // The tangent's direction v, unnormalised (a square root keeps the loop scalar where errno is
        // kept): projections onto the plane normal to it divide by |v|^2, and by nothing when v = 0.
        const float vx = p_after.x - p_before.x, vy = p_after.y - p_before.y, vz = p_after.z - p_before.z;
        const float squared = vx * vx + vy * vy + vz * vz;
        const bool moved = squared > 0.0f;
        const float inverse = (moved ? 1.0f : 0.0f) / (moved ? squared : 1.0f);
        // The Jacobian at the centre (map_jacobian), by rows.
        const float dx = cx - lane(m, map_stride, kRestOrigin), dy = cy - lane(m, map_stride, kRestOrigin + 1),
                    dz = cz - lane(m, map_stride, kRestOrigin + 2);
        const LaneVector jx = lane_jacobian_row(m, map_stride, 0, dx, dy, dz), jy = lane_jacobian_row(m, map_stride, 1, dx, dy, dz),
                         jz = lane_jacobian_row(m, map_stride, 2, dx, dy, dz);
        // section_diameter of the skinned semi-axes, normal to the skinned tangent.
        const LaneVector major = lane_apply(jx, jy, jz, r, nc, kMajor), minor = lane_apply(jx, jy, jz, r, nc, kMinor);
        const float along_a = dot(major, vx, vy, vz) * inverse, along_b = dot(minor, vx, vy, vz) * inverse;
        const float ax = major.x - along_a * vx, ay = major.y - along_a * vy, az = major.z - along_a * vz;
        const float bx = minor.x - along_b * vx, by = minor.y - along_b * vy, bz = minor.z - along_b * vz;
        const float squared_a = ax * ax + ay * ay + az * az, squared_b = bx * bx + by * by + bz * bz;
        // The ellipsoid's axes mapped by the Jacobian, as the entries of E = sum a a^T.
        const LaneVector u = lane_apply(jx, jy, jz, r, nc, kAxes), v = lane_apply(jx, jy, jz, r, nc, kAxes + 3),
                         w = lane_apply(jx, jy, jz, r, nc, kAxes + 6);
        float* o = out + k;
        o[(kOutCentre + 0) * kLaneChunk] = centre.x;
        o[(kOutCentre + 1) * kLaneChunk] = centre.y;
        o[(kOutCentre + 2) * kLaneChunk] = centre.z;
        o[kOutSquaredRadius * kLaneChunk] = squared_a > squared_b ? squared_a : squared_b;
        o[(kOutEntries + 0) * kLaneChunk] = u.x * u.x + v.x * v.x + w.x * w.x;
        o[(kOutEntries + 1) * kLaneChunk] = u.y * u.y + v.y * v.y + w.y * w.y;
        o[(kOutEntries + 2) * kLaneChunk] = u.z * u.z + v.z * v.z + w.z * w.z;
        o[(kOutEntries + 3) * kLaneChunk] = u.x * u.y + v.x * v.y + w.x * w.y;
        o[(kOutEntries + 4) * kLaneChunk] = u.y * u.z + v.y * v.z + w.y * w.z;
        o[(kOutEntries + 5) * kLaneChunk] = u.z * u.x + v.z * v.x + w.z * w.x;
    }
}

}  // namespace

glm::vec3 map_point(const ClusterMap& map, const glm::vec3& d) {
    const std::array<glm::vec3, 6>& q = map.quadratic;
    return map.origin + map.linear * d + q[0] * (d.x * d.x) + q[1] * (d.y * d.y) + q[2] * (d.z * d.z) +
           q[3] * (d.x * d.y) + q[4] * (d.y * d.z) + q[5] * (d.z * d.x);
}

glm::mat3 map_jacobian(const ClusterMap& map, const glm::vec3& d) {
    const std::array<glm::vec3, 6>& q = map.quadratic;
    return map.linear + glm::mat3(2.0f * d.x * q[0] + d.y * q[3] + d.z * q[5], 2.0f * d.y * q[1] + d.x * q[3] + d.z * q[4],
                                  2.0f * d.z * q[2] + d.y * q[4] + d.x * q[5]);
}

std::vector<GuideFrame> rest_frames(const LodAsset& asset) {
    const auto nc = static_cast<size_t>(asset.control_points);
    std::vector<GuideFrame> frames(asset.cluster_count() * nc);
    tbb::parallel_for(size_t{0}, asset.cluster_count(), [&](size_t c) {
        const GuideSet guides = guide_set(asset.cluster_guides[c], asset.rest_guides.data(), asset.control_points);
        for (size_t k = 0; k < nc; ++k)
            frames[c * nc + k] = guide_frame(asset.frame_kinds[c * nc + k], guides, static_cast<int>(k));
    });
    return frames;
}

std::vector<ClusterMap> identity_maps(std::span<const GuideFrame> rest_frames) {
    std::vector<ClusterMap> maps(rest_frames.size());
    for (size_t i = 0; i < maps.size(); ++i) maps[i] = ClusterMap{rest_frames[i].origin, rest_frames[i].origin, glm::mat3(1.0f)};
    return maps;
}

SkinningRest skinning_rest(const LodAsset& asset) {
    SkinningRest rest;
    rest.frames = rest_frames(asset);
    rest.stencils = skinning_stencils(asset, rest.frames);
    return rest;
}

namespace {

void check_deformed_guides(const LodAsset& asset, const SkinningRest& rest, std::span<const glm::vec3> deformed_guides) {
    const auto nc = static_cast<size_t>(asset.control_points);
    if (deformed_guides.size() != asset.rest_guides.size())
        throw Error("skin: expected " + std::to_string(asset.guide_count()) + " guides x " + std::to_string(nc) +
                    " points, got " + std::to_string(deformed_guides.size()) + " points");
    for (const glm::vec3& p : deformed_guides)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error("skin: deformed guides contain NaN or infinite coordinates");
    if (rest.frames.size() != asset.cluster_count() * nc || rest.stencils.stencils.size() != rest.frames.size())
        throw Error("skin: rest frames do not belong to this asset");
}

// The maps of L0 cluster c at its n_c control points into `out` (checked guides).
void maps_of_cluster(const LodAsset& asset, const SkinningRest& rest, std::span<const glm::vec3> deformed_guides, size_t c,
                     std::span<ClusterMap> out) {
    const auto nc = static_cast<size_t>(asset.control_points);
    const GuideSet deformed = guide_set(asset.cluster_guides[c], deformed_guides.data(), asset.control_points);
    for (size_t k = 0; k < nc; ++k) {
        const size_t i = c * nc + k;
        const GuideFrame& rest_frame = rest.frames[i];
        const GuideFrame frame = guide_frame(asset.frame_kinds[i], deformed, static_cast<int>(k));
        // Stored offsets are relative to the rest frame origin: the map is anchored there.
        const QuadraticMap map = stencil_map(rest.stencils, i, deformed_guides, rest_frame, frame, frame_map(rest_frame, frame),
                                             glm::dvec3(rest_frame.origin));
        ClusterMap& cluster_map = out[k];
        cluster_map = ClusterMap{rest_frame.origin, glm::vec3(map.origin), glm::mat3(map.linear)};
        for (size_t m = 0; m < 6; ++m) cluster_map.quadratic[m] = glm::vec3(map.quadratic[m]);
    }
}

}  // namespace

std::vector<ClusterMap> cluster_maps(const LodAsset& asset, const SkinningRest& rest,
                                     std::span<const glm::vec3> deformed_guides) {
    check_deformed_guides(asset, rest, deformed_guides);
    const auto nc = static_cast<size_t>(asset.control_points);
    std::vector<ClusterMap> maps(rest.frames.size());
    tbb::parallel_for(size_t{0}, asset.cluster_count(), [&](size_t c) {
        maps_of_cluster(asset, rest, deformed_guides, c, std::span<ClusterMap>(maps).subspan(c * nc, nc));
    });
    return maps;
}

std::vector<glm::vec3> resample_guides(const LodAsset& asset, const StrandSet& guide_curves) {
    if (guide_curves.curve_count() != asset.guide_count())
        throw Error("resample_guides: expected " + std::to_string(asset.guide_count()) + " guide curves, got " +
                    std::to_string(guide_curves.curve_count()));
    StrandSet resampled = resample_strands(guide_curves, {.points_per_curve = asset.control_points,
                                                          .subdivisions_per_segment = LodOptions{}.arc_length_subdivisions});
    return std::move(resampled.points);
}

MapTexels map_texels(const ClusterMap& map) {
    // glm matrices are column-major: linear[col][row].
    const std::array<glm::vec3, 6>& q = map.quadratic;
    MapTexels texels;
    texels[0] = glm::vec4(map.rest_origin, 0.0f);
    for (int r = 0; r < 3; ++r) {
        texels[1 + r] = glm::vec4(map.linear[0][r], map.linear[1][r], map.linear[2][r], map.origin[r]);
        texels[4 + r] = glm::vec4(q[0][r], q[1][r], q[2][r], 0.0f);
        texels[7 + r] = glm::vec4(q[3][r], q[4][r], q[5][r], 0.0f);
    }
    return texels;
}

FrameSkinning::FrameSkinning(const LodAsset& asset) : asset_(&asset) {
    // The stencils wait for the first update: a preview that never moves does not derive them.
    rest_.frames = rest_frames(asset);
    const auto nc = static_cast<size_t>(asset.control_points);
    const size_t clusters = asset.cluster_count();
    // The widest hair of each cluster and control point at rest, as LodAsset::skin measures it.
    for (size_t l = 0; l < asset.thick_levels.size(); ++l) {
        const ThickHairLevel& level = asset.thick_levels[l];
        std::vector<float>& widest = widest_rest_.emplace_back(clusters * kWidestFields * nc);
        tbb::parallel_for(size_t{0}, clusters, [&](size_t c) {
            float* lanes = widest.data() + c * kWidestFields * nc;
            auto put = [&](size_t field, size_t k, const glm::vec3& v) {
                for (int r = 0; r < 3; ++r) lanes[(field + static_cast<size_t>(r)) * nc + k] = v[r];
            };
            std::vector<float> best(nc, -1.0f);
            std::vector<RestSection> sections(nc);
            std::vector<glm::vec3> centres(nc), tangents(nc), majors(nc), minors(nc);
            std::vector<std::vector<glm::vec3>> semi_axes(nc);  // every hair's, per control point
            for (int32_t h = level.cluster_first[c]; h < level.cluster_first[c + 1]; ++h) {
                for (size_t k = 0; k < nc; ++k) {
                    sections[k] = asset.section(l, static_cast<size_t>(h), k);
                    centres[k] = rest_.frames[c * nc + k].origin + sections[k].centre_offset;
                }
                for (size_t k = 0; k < nc; ++k) {
                    const size_t before = k == 0 ? 0 : k - 1, after = std::min(k + 1, nc - 1);
                    const glm::vec3 tangent = unit_or_zero(centres[after] - centres[before]);
                    const glm::vec3 major = sections[k].major_axis * sections[k].radii.x;
                    const glm::vec3 minor = sections[k].minor_axis * sections[k].radii.y;
                    append_projected_semi_axes(tangent, major, minor, semi_axes[k]);
                    const float diameter = section_diameter(tangent, major, minor);
                    if (diameter > best[k]) {
                        best[k] = diameter;
                        tangents[k] = tangent;
                        majors[k] = major;
                        minors[k] = minor;
                        put(kBefore, k, centres[before]);
                        put(kCentre, k, centres[k]);
                        put(kAfter, k, centres[after]);
                    }
                }
            }
            for (size_t k = 0; k < nc; ++k) {
                put(kMajor, k, majors[k]);
                put(kMinor, k, minors[k]);
                const WidthEllipsoid ellipsoid = width_ellipsoid(tangents[k], majors[k], minors[k], semi_axes[k]);
                for (size_t axis = 0; axis < 3; ++axis) put(kAxes + 3 * axis, k, ellipsoid.axes[axis]);
                const float diameter = section_diameter(tangents[k], majors[k], minors[k]);
                lanes[kThinnestFraction * nc + k] = diameter > 0.0f ? thinnest_diameter(ellipsoid) / diameter : 0.0f;
            }
        });
    }
    widest_strand_radius_.assign(clusters, 0.0f);
    tbb::parallel_for(size_t{0}, clusters, [&](size_t c) {
        const auto [first, end] = asset.cluster_strands(c);
        uint16_t widest = 0;  // halves >= 0 order like their codes
        for (auto i = static_cast<size_t>(first); i < static_cast<size_t>(end); ++i)
            for (size_t k = 0; k < nc; ++k) widest = std::max(widest, asset.strand_radius_code(i, k));
        widest_strand_radius_[c] = decode_half(widest, asset.radius_exponent);
    });
    geometry_.cluster_bounds.resize(clusters);
    geometry_.levels.resize(asset.thick_levels.size());
    for (ThickHairGeometry& level : geometry_.levels) {
        level.widest.resize(clusters * nc);
        level.width_ellipsoid.resize(clusters * nc);
        level.thinnest.resize(clusters * nc);
    }
    texels_.resize(clusters * nc);
    set_maps(identity_maps(rest_.frames));
}

void FrameSkinning::update(std::span<const glm::vec3> deformed_guides) {
    if (rest_.stencils.stencils.empty()) rest_.stencils = skinning_stencils(*asset_, rest_.frames);
    check_deformed_guides(*asset_, rest_, deformed_guides);
    // One pass per cluster, the maps made and used while they are in cache (no [clusters * n_c] array
    // of them written and read back).
    const auto nc = static_cast<size_t>(asset_->control_points);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, asset_->cluster_count()), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<ClusterMap> maps(nc);  // scratch per range of clusters (thread_local costs a call per access here)
        std::vector<float> scratch;
        for (size_t c = range.begin(); c != range.end(); ++c) {
            maps_of_cluster(*asset_, rest_, deformed_guides, c, maps);
            set_cluster_maps(c, maps, scratch);
        }
    });
}

void FrameSkinning::set_maps(std::span<const ClusterMap> maps) {
    const auto nc = static_cast<size_t>(asset_->control_points);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, asset_->cluster_count()), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<float> scratch;
        for (size_t c = range.begin(); c != range.end(); ++c) set_cluster_maps(c, maps.subspan(c * nc, nc), scratch);
    });
}

void FrameSkinning::set_cluster_maps(size_t c, std::span<const ClusterMap> maps, std::vector<float>& scratch) {
    // maps: the cluster's n_c maps, maps[k] for control point k (global index c n_c + k).
    const auto nc = static_cast<size_t>(asset_->control_points);
    const size_t first = c * nc;
    glm::vec3 lower(std::numeric_limits<float>::infinity()), upper(-std::numeric_limits<float>::infinity());
    for (size_t k = 0; k < nc; ++k) {
        const ClusterMap& map = maps[k];
        texels_[first + k] = map_texels(map);
        // The box of the strands' rest offsets, mapped. About its centre e the map is
        // p(e) + J(e) u + Q(u) exactly (Q the quadratic terms): the linear part takes the box
        // |u_a| <= h_a to a parallelepiped whose bounding box is p(e) +- |J| h (|J| the entries'
        // absolute values: each coordinate sum_a J_ra u_a is largest with u_a = h_a sign(J_ra)), and
        // |Q_r(u)| <= sum_m |q_m,r| |u_a u_b| widens it by at most that much per coordinate.
        const QuantisationBox& box = asset_->offset_boxes[first + k];
        const glm::vec3 half = 0.5f * box.step * float(std::numeric_limits<uint16_t>::max());
        const glm::vec3 centre = box.lower + half;
        const glm::vec3 image = map_point(map, centre);
        const glm::mat3 jacobian = map_jacobian(map, centre);
        const std::array<glm::vec3, 6>& q = map.quadratic;
        const glm::vec3 reach = glm::abs(jacobian[0]) * half.x + glm::abs(jacobian[1]) * half.y + glm::abs(jacobian[2]) * half.z +
                                glm::abs(q[0]) * (half.x * half.x) + glm::abs(q[1]) * (half.y * half.y) +
                                glm::abs(q[2]) * (half.z * half.z) + glm::abs(q[3]) * (half.x * half.y) +
                                glm::abs(q[4]) * (half.y * half.z) + glm::abs(q[5]) * (half.z * half.x);
        lower = glm::min(lower, image - reach);
        upper = glm::max(upper, image + reach);
    }
    geometry_.cluster_bounds[c] = glm::vec4(0.5f * (lower + upper), 0.5f * glm::distance(lower, upper) + widest_strand_radius_[c]);
    // Each level's widest hairs, control points in vector lanes: the maps laid out field by field
    // (with the clamped neighbours at either end), then the kernel.
    const size_t map_stride = nc + 2;
    scratch.resize(kMapFields * map_stride + kSelectionFields * kLaneChunk);
    float* padded = scratch.data();
    float* selected = padded + kMapFields * map_stride;
    put_padded_maps(maps, padded);
    for (size_t l = 0; l < widest_rest_.size(); ++l) {
        const float* rest = widest_rest_[l].data() + c * kWidestFields * nc;
        ThickHairGeometry& level = geometry_.levels[l];
        for (size_t chunk = 0; chunk < nc; chunk += kLaneChunk) {
            const size_t count = std::min(kLaneChunk, nc - chunk);
            widest_hair_lanes(padded + chunk, map_stride, rest + chunk, nc, count, selected);
            for (size_t j = 0; j < count; ++j) {
                const size_t k = chunk + j;
                auto out = [&](size_t field) { return selected[field * kLaneChunk + j]; };
                const float diameter = 2.0f * std::sqrt(out(kOutSquaredRadius));
                level.widest[first + k] = glm::vec4(out(kOutCentre), out(kOutCentre + 1), out(kOutCentre + 2), diameter);
                for (size_t e = 0; e < 6; ++e) level.width_ellipsoid[first + k][e] = out(kOutEntries + e);
                level.thinnest[first + k] = rest[kThinnestFraction * nc + k] * diameter;
            }
        }
    }
}

LodGeometry LodAsset::skin(std::span<const glm::vec3> deformed_guides) const {
    return skin_geometry(*this, skinning_rest(*this), deformed_guides);
}

LodGeometry LodAsset::rest_geometry() const {
    // The rest pose maps every point to itself: no stencils to derive.
    return mapped_geometry(*this, identity_maps(rest_frames(*this)));
}

LodGeometry skin_geometry(const LodAsset& asset, const SkinningRest& rest, std::span<const glm::vec3> deformed_guides) {
    return mapped_geometry(asset, cluster_maps(asset, rest, deformed_guides));
}

LodGeometry mapped_geometry(const LodAsset& asset, std::span<const ClusterMap> maps) {
    const auto nc = static_cast<size_t>(asset.control_points);
    const size_t clusters = asset.cluster_count(), strands = asset.strand_count();
    const auto& strand_order = asset.strand_order;
    const auto& offset_boxes = asset.offset_boxes;
    const auto& strand_offset = asset.strand_offset;
    const auto& thick_levels = asset.thick_levels;
    const int radius_exponent = asset.radius_exponent;

    LodGeometry geometry;
    StrandSet& out = geometry.strands;
    out.points.resize(strands * nc);
    out.radius.resize(strands * nc);
    out.offsets.resize(strands + 1);
    for (size_t s = 0; s <= strands; ++s) out.offsets[s] = static_cast<int64_t>(s * nc);
    geometry.cluster_bounds.resize(clusters);
    tbb::parallel_for(size_t{0}, clusters, [&](size_t c) {
        glm::vec3 lower(std::numeric_limits<float>::infinity()), upper(-std::numeric_limits<float>::infinity());
        float widest = 0.0f;
        const auto [first, end] = asset.cluster_strands(c);
        for (auto i = static_cast<size_t>(first); i < static_cast<size_t>(end); ++i) {
            const auto s = static_cast<size_t>(strand_order[i]);
            for (size_t k = 0; k < nc; ++k) {
                const glm::vec3 p = map_point(maps[c * nc + k], offset_boxes[c * nc + k].decode(strand_offset[i * nc + k]));
                const float radius = decode_half(asset.strand_radius_code(i, k), radius_exponent);
                out.points[s * nc + k] = p;
                out.radius[s * nc + k] = radius;
                lower = glm::min(lower, p);
                upper = glm::max(upper, p);
                widest = std::max(widest, radius);
            }
        }
        geometry.cluster_bounds[c] = glm::vec4(0.5f * (lower + upper), 0.5f * glm::distance(lower, upper) + widest);
    });

    for (size_t l = 0; l < thick_levels.size(); ++l) {
        const ThickHairLevel& level = thick_levels[l];
        ThickHairGeometry& g = geometry.levels.emplace_back();
        const size_t count = level.hair_count() * nc;
        g.centre.resize(count);
        g.tangent.resize(count);
        g.major.resize(count);
        g.minor.resize(count);
        g.corners.resize(count);
        g.widest.resize(clusters * nc);
        g.width_ellipsoid.resize(clusters * nc);
        g.thinnest.resize(clusters * nc);
        tbb::parallel_for(size_t{0}, clusters, [&](size_t c) {
            std::vector<size_t> widest_hair(nc);
            for (int32_t h = level.cluster_first[c]; h < level.cluster_first[c + 1]; ++h) {
                const size_t first = static_cast<size_t>(h) * nc;
                for (size_t k = 0; k < nc; ++k) {
                    const size_t at = first + k;
                    const RestSection rest = asset.section(l, static_cast<size_t>(h), k);
                    const ClusterMap& map = maps[c * nc + k];
                    g.centre[at] = map_point(map, rest.centre_offset);
                    const glm::mat3 jacobian = map_jacobian(map, rest.centre_offset);
                    g.major[at] = jacobian * (rest.major_axis * rest.radii.x);
                    g.minor[at] = jacobian * (rest.minor_axis * rest.radii.y);
                    // The cross-section is skinned as a small one: its axes by the map's
                    // Jacobian at its centre (the shader does the same).
                    g.corners[at] = {g.centre[at] + g.major[at], g.centre[at] - g.major[at], g.centre[at] + g.minor[at],
                                     g.centre[at] - g.minor[at]};
                }
                for (size_t k = 0; k < nc; ++k) {
                    const glm::vec3 step = g.centre[first + std::min(k + 1, nc - 1)] - g.centre[first + (k == 0 ? 0 : k - 1)];
                    const float length = glm::length(step);
                    g.tangent[first + k] = length > 0.0f ? step / length : glm::vec3(0.0f);
                    const float diameter = section_diameter(g.tangent[first + k], g.major[first + k], g.minor[first + k]);
                    glm::vec4& widest = g.widest[c * nc + k];
                    if (h == level.cluster_first[c] || diameter > widest.w) {
                        widest = glm::vec4(g.centre[first + k], diameter);
                        widest_hair[k] = first + k;
                    }
                }
            }
            std::vector<glm::vec3> semi_axes;
            for (size_t k = 0; k < nc; ++k) {
                semi_axes.clear();
                for (int32_t h = level.cluster_first[c]; h < level.cluster_first[c + 1]; ++h) {
                    const size_t at = static_cast<size_t>(h) * nc + k;
                    append_projected_semi_axes(g.tangent[at], g.major[at], g.minor[at], semi_axes);
                }
                const size_t w = widest_hair[k];
                const WidthEllipsoid ellipsoid = width_ellipsoid(g.tangent[w], g.major[w], g.minor[w], semi_axes);
                g.width_ellipsoid[c * nc + k] = symmetric_entries(ellipsoid);
                g.thinnest[c * nc + k] = thinnest_diameter(ellipsoid);
            }
        });
    }
    return geometry;
}

}  // namespace hairlod
