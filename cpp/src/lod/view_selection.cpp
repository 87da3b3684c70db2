#include "hairlod/lod/view_selection.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "hairlod/core/error.h"

namespace hairlod {

void append_draw_indices(const Selection& selection, int level, int control_points, DrawPrimitive primitive,
                         std::vector<uint32_t>& out) {
    if (control_points < 2) throw Error("draw indices: control_points must be >= 2, got " + std::to_string(control_points));
    const auto nc = static_cast<uint32_t>(control_points);
    for (const DrawRange& draw : selection.draws) {
        if (draw.level != level) continue;
        const auto last_segment = static_cast<uint32_t>(draw.first_segment + draw.segment_count);
        for (auto item = static_cast<uint32_t>(draw.first); item < static_cast<uint32_t>(draw.first + draw.count); ++item) {
            for (auto s = static_cast<uint32_t>(draw.first_segment); s < last_segment; ++s) {
                const uint32_t k = item * nc + s;
                if (primitive == DrawPrimitive::segments) {
                    out.push_back(k);
                } else if (primitive == DrawPrimitive::lines) {
                    out.insert(out.end(), {k, k + 1});
                } else {
                    // Control points k and k + 1 span the quad (2k, 2k + 1, 2k + 2, 2k + 3).
                    const uint32_t v = 2 * k;
                    out.insert(out.end(), {v, v + 1, v + 2, v + 1, v + 3, v + 2});
                }
            }
        }
    }
}

ViewSelection::ViewSelection(const LodAsset& asset, LodGeometry geometry)
    : asset_(&asset), level_versions_(static_cast<size_t>(level_count()), 0) {
    set_geometry(std::move(geometry));
}

void ViewSelection::set_geometry(LodGeometry geometry) {
    bool fits = geometry.levels.size() == asset_->thick_levels.size() && geometry.cluster_bounds.size() == asset_->cluster_count();
    for (const ThickHairGeometry& level : geometry.levels)
        fits = fits && level.widest.size() == asset_->cluster_count() * static_cast<size_t>(asset_->control_points);
    if (!fits) throw Error("view selection: geometry does not belong to this asset");
    geometry_ = std::move(geometry);
}

bool ViewSelection::update(const Camera& camera, float width_px) {
    if (!started_) {
        selection_ = select_initial(*asset_, geometry_, camera, width_px, SelectionThreads::caller);
        started_ = true;
        for (uint64_t& version : level_versions_) ++version;
        return true;
    }
    const std::vector<uint8_t> level = selection_.level, visible = selection_.visible;
    // Huang 2025 Eq. 16 run until it changes nothing: continuous motion moves a segment one level, as one step
    // would, and a view that jumped shows its levels on its first frame instead of coarse ones
    // refining over several.
    select_deferred_in_place(*asset_, geometry_, camera, width_px, selection_, DeferredSteps::until_stable,
                             SelectionThreads::caller);
    return count_changes(level, visible);
}

bool ViewSelection::count_changes(const std::vector<uint8_t>& level, const std::vector<uint8_t>& visible) {
    const auto segments = static_cast<size_t>(selection_.segments);
    std::vector<uint8_t> moved(level_versions_.size(), 0);
    for (size_t c = 0; c < visible.size(); ++c) {
        const bool was = visible[c] != 0, is = selection_.visible[c] != 0;
        // Most clusters keep their levels from one frame to the next: one comparison each.
        if ((!was && !is) || (was == is && std::memcmp(&level[c * segments], &selection_.level[c * segments], segments) == 0))
            continue;
        for (size_t at = c * segments; at < (c + 1) * segments; ++at) {
            const uint8_t before = level[at], now = selection_.level[at];
            if (was == is && before == now) continue;
            // Levels stay below level_count(); the bound only guards the write.
            if (was && before < moved.size()) moved[before] = 1;
            if (is && now < moved.size()) moved[now] = 1;
        }
    }
    bool changed = false;
    for (size_t l = 0; l < moved.size(); ++l) {
        level_versions_[l] += moved[l];
        changed = changed || moved[l] != 0;
    }
    return changed;
}

std::vector<uint32_t> ViewSelection::indices(int level, DrawPrimitive primitive) const {
    if (level < 0 || level >= level_count())
        throw Error("view selection: level " + std::to_string(level) + " out of range [0, " +
                    std::to_string(level_count()) + ")");
    std::vector<uint32_t> out;
    append_draw_indices(selection_, level, asset_->control_points, primitive, out);
    return out;
}

void ViewSelection::frame_levels(std::vector<float>& levels, std::vector<uint8_t>& present,
                                 std::vector<int8_t>& whole) const {
    const size_t clusters = selection_.visible.size(), segments = static_cast<size_t>(selection_.segments);
    const auto level_total = static_cast<size_t>(level_count());
    levels.resize(clusters * segments);
    present.assign(clusters * level_total, 0);
    whole.assign(clusters, -1);
    for (size_t c = 0; c < clusters; ++c) {
        const bool visible = selection_.visible[c] != 0;
        bool one_level = visible && segments > 0;
        for (size_t s = 0; s < segments; ++s) {
            const uint8_t level = selection_.level[c * segments + s];
            levels[c * segments + s] = visible ? static_cast<float>(level) : -1.0f;
            if (visible && level < level_total) present[c * level_total + level] = 1;
            one_level = one_level && level == selection_.level[c * segments];
        }
        if (one_level && selection_.level[c * segments] < level_total) whole[c] = static_cast<int8_t>(selection_.level[c * segments]);
    }
}

std::vector<int64_t> ViewSelection::segments_per_level() const {
    std::vector<int64_t> segments(static_cast<size_t>(level_count()), 0);
    for (const DrawRange& draw : selection_.draws)
        segments[static_cast<size_t>(draw.level)] += static_cast<int64_t>(draw.count) * draw.segment_count;
    return segments;
}

template <typename Chord>
void ViewSelection::visit_strided_chords(std::span<const int32_t> cluster_strides, Chord&& chord) const {
    if (cluster_strides.size() != asset_->cluster_count())
        throw Error("strided strands: cluster_strides needs one stride per L0 cluster (" +
                    std::to_string(asset_->cluster_count()) + "), got " + std::to_string(cluster_strides.size()));
    for (int32_t stride : cluster_strides)
        if (stride < 1) throw Error("strided strands: strides must be >= 1, got " + std::to_string(stride));
    const int strands = level_count() - 1, last = asset_->control_points - 1;
    // Draw ranges come per cluster in segment order: a chord spanning two runs is visited once.
    int32_t cluster = -1, next_free = 0;
    for (const DrawRange& draw : selection_.draws) {
        if (draw.level != strands) continue;
        if (draw.cluster != cluster) cluster = draw.cluster, next_free = 0;
        const int32_t stride = cluster_strides[static_cast<size_t>(draw.cluster)];
        const int32_t from = std::max(draw.first_segment / stride * stride, next_free);
        for (int32_t a = from; a < draw.first_segment + draw.segment_count; a += stride) {
            chord(draw.first, draw.count, a, std::min(a + stride, last));
            next_free = a + stride;
        }
    }
}

std::vector<uint32_t> ViewSelection::strided_strand_lines(std::span<const int32_t> cluster_strides) const {
    std::vector<uint32_t> out;
    const auto nc = static_cast<uint32_t>(asset_->control_points);
    visit_strided_chords(cluster_strides, [&](int32_t first, int32_t count, int32_t a, int32_t b) {
        for (auto item = static_cast<uint32_t>(first); item < static_cast<uint32_t>(first + count); ++item)
            out.insert(out.end(), {item * nc + static_cast<uint32_t>(a), item * nc + static_cast<uint32_t>(b)});
    });
    return out;
}

int64_t ViewSelection::strided_strand_segments(std::span<const int32_t> cluster_strides) const {
    int64_t chords = 0;
    visit_strided_chords(cluster_strides, [&](int32_t, int32_t count, int32_t, int32_t) { chords += count; });
    return chords;
}

void level_blocks(std::span<const uint8_t> present, size_t level_count, std::span<const int8_t> whole, int level,
                  std::span<const int64_t> block_first, std::vector<uint8_t>& draw, std::vector<uint8_t>& one_level) {
    const size_t clusters = whole.size();
    if (level_count == 0 || present.size() != clusters * level_count)
        throw Error("level_blocks: present must hold level_count entries per cluster of whole");
    if (level < 0 || static_cast<size_t>(level) >= level_count)
        throw Error("level_blocks: level " + std::to_string(level) + " outside [0, " + std::to_string(level_count) + ")");
    if (block_first.empty() || block_first.front() != 0 || static_cast<size_t>(block_first.back()) != clusters ||
        !std::is_sorted(block_first.begin(), block_first.end()))
        throw Error("level_blocks: block_first must rise from 0 to the cluster count");
    const size_t blocks = block_first.size() - 1;
    draw.assign(blocks, 0);
    one_level.assign(blocks, 0);
    for (size_t b = 0; b < blocks; ++b) {
        bool any = false, all = block_first[b] < block_first[b + 1];
        for (auto c = static_cast<size_t>(block_first[b]); c < static_cast<size_t>(block_first[b + 1]); ++c) {
            any = any || present[c * level_count + static_cast<size_t>(level)] != 0;
            all = all && whole[c] == level;
        }
        draw[b] = any;
        one_level[b] = all;
    }
}

}  // namespace hairlod
