#pragma once
// Per-view LoD state for interactive drawing (hair-lod-aggregated-bcsdf.txt Sec. 5.2): the rest (or
// one skinned) geometry, the current Selection, and the index lists a renderer draws from it.
// The first update makes the initial selection (Sec. 5.1 step 5); later updates run Huang 2025 Eq. 16 from the
// previous one until it changes nothing: a camera moving smoothly changes a level by one between
// frames, and one that jumps gets its levels at once (no frames of coarse hair first). Index lists
// refer to vertex buffers laid out item-major with n_c control points per item:
// thick hairs of a level in asset order, strands in hierarchy order (LodAsset::strand_order).
#include <cstdint>
#include <span>
#include <vector>

#include "hairlod/lod/lod_asset.h"
#include "hairlod/lod/selection.h"

namespace hairlod {

// LINES: one vertex per control point, 2 indices per segment. STRIPS: camera-facing strips with
// vertices 2k and 2k + 1 on either side of control point k, 6 indices (2 triangles) per segment.
// SEGMENTS: one index per segment, its first control point k (item * n_c + segment), for a shader
// that fetches the segment's points itself: a sixth of the strips' indices.
enum class DrawPrimitive { lines, strips, segments };

// Appends the indices of every range of `selection` at `level` to `out`.
void append_draw_indices(const Selection& selection, int level, int control_points, DrawPrimitive primitive,
                         std::vector<uint32_t>& out);

class ViewSelection {
public:
    // `asset` must outlive this object; `geometry` is its rest or skinned geometry.
    ViewSelection(const LodAsset& asset, LodGeometry geometry);

    // Selects for `camera`: the initial selection on the first call (or after reset), else Huang 2025 Eq. 16
    // from the current levels until stable. Returns whether any level, visibility or the draw list
    // changed. Runs in the calling thread (SelectionThreads::caller: it runs inside a viewport's draw).
    bool update(const Camera& camera, float width_px);
    void reset() { started_ = false; }
    // Replaces the geometry when the guides move (FrameSkinning::selection_geometry, or
    // LodAsset::skin); the next update runs Huang 2025 Eq. 16 from the current levels, as for a moving camera.
    // Throws Error when the geometry does not belong to the asset.
    void set_geometry(LodGeometry geometry);

    const Selection& selection() const { return selection_; }
    // Per level, a count that rises whenever the segments selected at that level change (which
    // visible clusters have which of their segments at it): an index list built from indices() at
    // one count stays right until the count moves, without comparing the selections.
    const std::vector<uint64_t>& level_versions() const { return level_versions_; }
    const LodGeometry& geometry() const { return geometry_; }
    int level_count() const { return static_cast<int>(asset_->thick_levels.size()) + 1; }  // the strands last

    std::vector<uint32_t> indices(int level, DrawPrimitive primitive) const;
    // What a renderer drawing from static per-cluster buffers needs each frame, in one pass:
    // `levels` [clusters * segments] the selected level of each L0 cluster and segment as a float,
    // -1 for clusters outside the view (a texture the shader compares with the level it draws);
    // `present` [clusters * level_count()] 1 where a visible cluster has a segment at that level;
    // `whole` [clusters] the level every segment of a visible cluster is at, -1 where they differ or
    // the cluster is culled (its segments need no per-fragment test of the level).
    void frame_levels(std::vector<float>& levels, std::vector<uint8_t>& present, std::vector<int8_t>& whole) const;
    // Segments selected per level (thick hairs or strands times their selected segments).
    std::vector<int64_t> segments_per_level() const;
    // The strands drawn through fewer control points (vertex LoD, vertex_lod.h): each L0 cluster's
    // strands at its stride (`cluster_strides` [clusters], >= 1) as the chords (a, min(a + s, n_c -
    // 1)), a = 0, s, 2s, ..., that span a segment selected at the strand level, each once. LINES
    // indices [2 per chord] in the strand layout of indices(); and the number of chords (what is drawn
    // in place of the strands' segments_per_level()).
    std::vector<uint32_t> strided_strand_lines(std::span<const int32_t> cluster_strides) const;
    int64_t strided_strand_segments(std::span<const int32_t> cluster_strides) const;

private:
    // Calls chord(cluster, first strand, strand count, a, b) for every chord the strided strands draw.
    template <typename Chord>
    void visit_strided_chords(std::span<const int32_t> cluster_strides, Chord&& chord) const;

    // Raises the versions of the levels whose selected segments differ between `level`, `visible`
    // (the selection before an update) and selection_; whether any did (a culled cluster keeps its
    // levels, so a change of the selection is a change of some level's segments).
    bool count_changes(const std::vector<uint8_t>& level, const std::vector<uint8_t>& visible);

    const LodAsset* asset_;
    LodGeometry geometry_;
    Selection selection_;
    std::vector<uint64_t> level_versions_;
    bool started_ = false;
};

// Per block of L0 clusters [block_first[b], block_first[b + 1]) of one level's static buffers, from
// ViewSelection::frame_levels' `present` [clusters * level_count] and `whole` [clusters]: `draw` 1
// where some visible cluster of the block has a segment at `level`, `one_level` 1 where every cluster
// of the block is visible with all its segments at it (a renderer then needs no per-fragment test).
void level_blocks(std::span<const uint8_t> present, size_t level_count, std::span<const int8_t> whole, int level,
                  std::span<const int64_t> block_first, std::vector<uint8_t>& draw, std::vector<uint8_t>& one_level);

}  // namespace hairlod
