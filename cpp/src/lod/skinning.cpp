#include "hairlod/lod/skinning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hairlod/core/error.h"
#include "hairlod/curves/resample.h"
#include "hairlod/lod/compact.h"
#include "hairlod/lod/cross_section.h"

namespace hairlod {

namespace {

glm::vec3 skin_point(const ClusterMap& map, const glm::vec3& rest_point) {
    return map_point(map, rest_point - map.rest_origin);
}

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
        std::vector<WidestRest>& widest = widest_rest_.emplace_back(clusters * nc);
        tbb::parallel_for(size_t{0}, clusters, [&](size_t c) {
            std::vector<float> best(nc, -1.0f);
            std::vector<RestSection> sections(nc);
            std::vector<glm::vec3> centres(nc), tangents(nc);
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
                        widest[c * nc + k] = WidestRest{centres[before], centres[k], centres[after], major, minor, {}, 0.0f};
                    }
                }
            }
            for (size_t k = 0; k < nc; ++k) {
                WidestRest& rest = widest[c * nc + k];
                rest.ellipsoid = width_ellipsoid(tangents[k], rest.major, rest.minor, semi_axes[k]);
                const float diameter = section_diameter(tangents[k], rest.major, rest.minor);
                rest.thinnest_fraction = diameter > 0.0f ? thinnest_diameter(rest.ellipsoid) / diameter : 0.0f;
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
        std::vector<glm::vec3> centres(nc);
        for (size_t c = range.begin(); c != range.end(); ++c) {
            maps_of_cluster(*asset_, rest_, deformed_guides, c, maps);
            set_cluster_maps(c, maps, centres);
        }
    });
}

void FrameSkinning::set_maps(std::span<const ClusterMap> maps) {
    const auto nc = static_cast<size_t>(asset_->control_points);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, asset_->cluster_count()), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<glm::vec3> centres(nc);
        for (size_t c = range.begin(); c != range.end(); ++c) set_cluster_maps(c, maps.subspan(c * nc, nc), centres);
    });
}

void FrameSkinning::set_cluster_maps(size_t c, std::span<const ClusterMap> maps, std::vector<glm::vec3>& centres) {
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
    // The widest hair's centres skinned once per control point: where the widest hair at k - 1 or
    // k + 1 is the same hair (its rest centre there is this hair's `before` / `after`), its skinned
    // centre is reused for the tangent, the same value computed once.
    for (size_t l = 0; l < widest_rest_.size(); ++l) {
        const WidestRest* widest = widest_rest_[l].data() + first;
        for (size_t k = 0; k < nc; ++k) centres[k] = skin_point(maps[k], widest[k].centre);
        for (size_t k = 0; k < nc; ++k) {
            const size_t before = k == 0 ? k : k - 1, after = k + 1 == nc ? k : k + 1;
            const WidestRest& rest = widest[k];
            const glm::vec3 at_after = rest.after == widest[after].centre ? centres[after] : skin_point(maps[after], rest.after);
            const glm::vec3 at_before = rest.before == widest[before].centre ? centres[before] : skin_point(maps[before], rest.before);
            const glm::vec3 tangent = unit_or_zero(at_after - at_before);
            const glm::mat3 jacobian = map_jacobian(maps[k], rest.centre - maps[k].rest_origin);
            const glm::vec3 major = jacobian * rest.major, minor = jacobian * rest.minor;
            const float diameter = section_diameter(tangent, major, minor);
            geometry_.levels[l].widest[first + k] = glm::vec4(centres[k], diameter);
            geometry_.levels[l].width_ellipsoid[first + k] = symmetric_entries(mapped(rest.ellipsoid, jacobian));
            geometry_.levels[l].thinnest[first + k] = rest.thinnest_fraction * diameter;
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
