#include "hairlod/lod/view_selection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "hairlod/core/error.h"
#include "hanging_hair.h"

namespace hairlod {
namespace {

StrandSet hanging_hair(size_t curves) { return testing::hanging_hair(curves, 8, 7); }

Camera camera_at(float distance, glm::vec3 direction = {1.0f, 0.3f, 0.2f}) {
    const glm::vec3 target(0, 0, -0.3f);
    Camera camera;
    camera.view = glm::lookAt(target + distance * glm::normalize(direction), target, glm::vec3(0, 0, 1));
    camera.projection = glm::perspective(glm::radians(45.0f), 4.0f / 3.0f, 0.01f, 1000.0f);
    camera.viewport = {800.0f, 600.0f};
    return camera;
}

class ViewSelectionTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        asset_ = new LodAsset(build_lod(hanging_hair(1500), {.guides = 12, .levels = 5, .control_points = 6, .seed = 3}));
    }
    static void TearDownTestSuite() { delete asset_; }
    static LodAsset* asset_;

    // Items of `level`: its thick hairs, or the strands at the finest level.
    static size_t items(int level) {
        return level < static_cast<int>(asset_->thick_levels.size())
                   ? asset_->thick_levels[static_cast<size_t>(level)].member_first.size() - 1
                   : asset_->strand_count();
    }
};
LodAsset* ViewSelectionTest::asset_ = nullptr;

TEST_F(ViewSelectionTest, StaticCameraConvergesToTheInitialSelection) {
    ViewSelection view(*asset_, asset_->rest_geometry());
    const Camera far = camera_at(40.0f), near = camera_at(2.5f);
    EXPECT_TRUE(view.update(far, 2.0f));  // the first update selects from scratch
    // Jumping close: the first frame there already has the levels (Huang 2025 Eq. 16 run until stable), which
    // one Huang 2025 Eq. 16 step a frame reached only after several frames of coarser hair.
    const Selection initial = select_initial(*asset_, view.geometry(), near, 2.0f);
    Selection one_step = view.selection();
    select_deferred_in_place(*asset_, view.geometry(), near, 2.0f, one_step);
    EXPECT_NE(one_step.level, initial.level);  // the jump spans more than one level somewhere
    EXPECT_TRUE(view.update(near, 2.0f));
    EXPECT_EQ(view.selection().level, initial.level);
    EXPECT_EQ(view.selection().visible, initial.visible);
    EXPECT_FALSE(view.update(near, 2.0f));
    view.reset();
    EXPECT_TRUE(view.update(near, 2.0f));
}

TEST_F(ViewSelectionTest, LevelVersionsMoveExactlyWhenTheirSegmentsChange) {
    // Per level, the set of visible (cluster, segment) pairs at it: what an index list of the level draws.
    const auto at_level = [](const Selection& selection, int level) {
        std::vector<size_t> segments;
        for (size_t at = 0; at < selection.level.size(); ++at)
            if (selection.visible[at / static_cast<size_t>(selection.segments)] && selection.level[at] == level) segments.push_back(at);
        return segments;
    };
    ViewSelection view(*asset_, asset_->rest_geometry());
    const int levels = view.level_count();
    ASSERT_EQ(view.level_versions().size(), static_cast<size_t>(levels));
    view.update(camera_at(40.0f), 2.0f);
    std::vector<uint64_t> versions = view.level_versions();
    Selection before = view.selection();
    int moved = 0, kept = 0;
    // A dolly in, a turn that culls clusters, and a static frame.
    std::vector<Camera> cameras;
    for (float distance = 30.0f; distance > 1.0f; distance *= 0.8f) cameras.push_back(camera_at(distance));
    cameras.push_back(camera_at(1.2f, {0.0f, 1.0f, 0.1f}));
    cameras.push_back(cameras.back());
    for (const Camera& camera : cameras) {
        view.update(camera, 2.0f);
        for (int level = 0; level < levels; ++level) {
            const bool changed = at_level(before, level) != at_level(view.selection(), level);
            const auto l = static_cast<size_t>(level);
            EXPECT_EQ(view.level_versions()[l] != versions[l], changed) << "level " << level;
            EXPECT_GE(view.level_versions()[l], versions[l]);
            (changed ? moved : kept) += 1;
        }
        versions = view.level_versions();
        before = view.selection();
    }
    EXPECT_GT(moved, 5);
    EXPECT_GT(kept, 5);
    // A reset selects from scratch: every list is built again.
    view.reset();
    view.update(cameras.back(), 2.0f);
    for (int level = 0; level < levels; ++level)
        EXPECT_GT(view.level_versions()[static_cast<size_t>(level)], versions[static_cast<size_t>(level)]);
}

TEST_F(ViewSelectionTest, IndicesCoverEveryVisibleSegmentOnce) {
    for (const float distance : {2.0f, 6.0f, 30.0f}) {
        ViewSelection view(*asset_, asset_->rest_geometry());
        view.update(camera_at(distance), 2.0f);
        const Selection& selection = view.selection();
        const auto nc = static_cast<uint32_t>(asset_->control_points);
        const std::vector<int64_t> segments = view.segments_per_level();
        // Each visible cluster's n_c - 1 segments are drawn at exactly one level each.
        std::vector<int> drawn(selection.visible.size() * static_cast<size_t>(selection.segments), 0);
        for (const DrawRange& draw : selection.draws)
            for (int s = draw.first_segment; s < draw.first_segment + draw.segment_count; ++s)
                ++drawn[static_cast<size_t>(draw.cluster) * selection.segments + static_cast<size_t>(s)];
        for (size_t c = 0; c < selection.visible.size(); ++c)
            for (int s = 0; s < selection.segments; ++s)
                EXPECT_EQ(drawn[c * selection.segments + static_cast<size_t>(s)], selection.visible[c] ? 1 : 0);
        for (int level = 0; level < view.level_count(); ++level) {
            const std::vector<uint32_t> lines = view.indices(level, DrawPrimitive::lines);
            const std::vector<uint32_t> strips = view.indices(level, DrawPrimitive::strips);
            ASSERT_EQ(lines.size(), 2 * static_cast<size_t>(segments[static_cast<size_t>(level)]));
            ASSERT_EQ(strips.size(), 6 * static_cast<size_t>(segments[static_cast<size_t>(level)]));
            const auto vertices = static_cast<uint32_t>(items(level)) * nc;
            if (!lines.empty()) {
                EXPECT_LT(*std::max_element(lines.begin(), lines.end()), vertices);
                EXPECT_LT(*std::max_element(strips.begin(), strips.end()), 2 * vertices);
            }
            // A line never joins two items: both ends belong to the same item.
            for (size_t i = 0; i < lines.size(); i += 2) {
                EXPECT_EQ(lines[i] / nc, lines[i + 1] / nc);
                EXPECT_EQ(lines[i + 1], lines[i] + 1);
            }
            // One index per segment, its first point: the lines' first ends, and the strip's quad
            // (2k, 2k + 1, 2k + 2, 2k + 1, 2k + 3, 2k + 2) of the same k.
            const std::vector<uint32_t> starts = view.indices(level, DrawPrimitive::segments);
            ASSERT_EQ(starts.size(), static_cast<size_t>(segments[static_cast<size_t>(level)]));
            for (size_t i = 0; i < starts.size(); ++i) {
                EXPECT_EQ(starts[i], lines[2 * i]);
                EXPECT_EQ(2 * starts[i], strips[6 * i]);
                EXPECT_EQ(2 * starts[i] + 3, strips[6 * i + 4]);
                EXPECT_LT(starts[i] % nc, nc - 1);  // a segment starts before the item's last point
            }
        }
    }
}

// The strands drawn at a stride per cluster (vertex LoD): every chord spanning a selected strand
// segment, once, each within one strand, starting at a multiple of its cluster's stride.
TEST_F(ViewSelectionTest, StridedStrandsCoverTheSelectedSegmentsWithChords) {
    ViewSelection view(*asset_, asset_->rest_geometry());
    view.update(camera_at(2.0f), 2.0f);
    const auto nc = static_cast<uint32_t>(asset_->control_points);
    const int strands = view.level_count() - 1;
    const std::vector<uint32_t> segments = view.indices(strands, DrawPrimitive::lines);
    ASSERT_FALSE(segments.empty());
    std::vector<int32_t> strides(asset_->cluster_count());
    for (size_t c = 0; c < strides.size(); ++c) strides[c] = std::array<int32_t, 4>{1, 2, 3, 8}[c % 4];
    std::vector<int32_t> strand_stride(asset_->strand_count());
    for (size_t c = 0; c < asset_->cluster_count(); ++c) {
        const auto [first, end] = asset_->cluster_strands(c);
        for (int32_t i = first; i < end; ++i) strand_stride[static_cast<size_t>(i)] = strides[c];
    }
    const std::vector<uint32_t> chords = view.strided_strand_lines(strides);
    ASSERT_EQ(chords.size(), 2 * static_cast<size_t>(view.strided_strand_segments(strides)));
    std::set<std::pair<uint32_t, uint32_t>> drawn;
    for (size_t i = 0; i < chords.size(); i += 2) {
        const uint32_t item = chords[i] / nc, a = chords[i] % nc, b = chords[i + 1] - item * nc;
        const auto stride = static_cast<uint32_t>(strand_stride[item]);
        EXPECT_EQ(a % stride, 0u);
        EXPECT_EQ(b, std::min(a + stride, nc - 1));
        EXPECT_TRUE(drawn.insert({chords[i], chords[i + 1]}).second) << "a chord drawn twice";
    }
    // Each selected segment lies on a drawn chord, and each chord holds a selected segment.
    std::set<uint32_t> starts;
    for (size_t i = 0; i < segments.size(); i += 2) {
        const uint32_t item = segments[i] / nc, k = segments[i] % nc, stride = static_cast<uint32_t>(strand_stride[item]);
        const uint32_t a = k / stride * stride;
        EXPECT_TRUE(drawn.count({item * nc + a, item * nc + std::min(a + stride, nc - 1)})) << item << " " << k;
        starts.insert(item * nc + a);
    }
    EXPECT_EQ(starts.size(), drawn.size());
    EXPECT_THROW(view.strided_strand_lines(std::span(strides).first(strides.size() - 1)), Error);
}

// The per-frame texture and presence flags restate the selection: the level of each visible
// cluster and segment, -1 for culled clusters, and a flag per (visible cluster, level in use);
// a camera that sees only part of the hair culls some clusters; and per cluster the level all its
// segments share, where they do and it is visible.
TEST_F(ViewSelectionTest, FrameLevelsRestateTheSelection) {
    for (const auto& [distance, direction] : {std::pair{6.0f, glm::vec3(1.0f, 0.3f, 0.2f)}, {0.4f, glm::vec3(0.2f, 1.0f, 0.1f)}}) {
        ViewSelection view(*asset_, asset_->rest_geometry());
        view.update(camera_at(distance, direction), 2.0f);
        const Selection& selection = view.selection();
        std::vector<float> levels;
        std::vector<uint8_t> present;
        std::vector<int8_t> whole;
        view.frame_levels(levels, present, whole);
        const size_t clusters = selection.visible.size(), segments = static_cast<size_t>(selection.segments);
        const auto level_count = static_cast<size_t>(view.level_count());
        ASSERT_EQ(levels.size(), clusters * segments);
        ASSERT_EQ(present.size(), clusters * level_count);
        std::vector<uint8_t> expected_present(present.size(), 0);
        for (size_t c = 0; c < clusters; ++c)
            for (size_t s = 0; s < segments; ++s) {
                const uint8_t level = selection.level[c * segments + s];
                EXPECT_EQ(levels[c * segments + s], selection.visible[c] ? static_cast<float>(level) : -1.0f);
                if (selection.visible[c]) expected_present[c * level_count + level] = 1;
            }
        EXPECT_EQ(present, expected_present);
        ASSERT_EQ(whole.size(), clusters);
        size_t whole_clusters = 0;
        for (size_t c = 0; c < clusters; ++c) {
            const auto first = selection.level.begin() + static_cast<std::ptrdiff_t>(c * segments);
            const bool one_level = std::all_of(first, first + static_cast<std::ptrdiff_t>(segments), [&](uint8_t level) { return level == *first; });
            EXPECT_EQ(whole[c], selection.visible[c] && one_level ? static_cast<int8_t>(*first) : int8_t{-1}) << c;
            whole_clusters += whole[c] >= 0;
        }
        EXPECT_GT(whole_clusters, 0u);
        if (distance < 1.0f) {
            EXPECT_NE(std::count(selection.visible.begin(), selection.visible.end(), uint8_t{0}), 0) << "some cluster culled";
        }
    }
}

TEST_F(ViewSelectionTest, FartherViewsDrawFewerSegments) {
    // Cameras that see the whole hair: the drawn segments never grow with distance, and far away
    // only thick hairs are drawn.
    int64_t previous_total = std::numeric_limits<int64_t>::max();
    std::vector<int64_t> segments;
    for (const float distance : {5.0f, 20.0f, 80.0f, 400.0f}) {
        ViewSelection view(*asset_, asset_->rest_geometry());
        view.update(camera_at(distance), 2.0f);
        segments = view.segments_per_level();
        const int64_t total = std::accumulate(segments.begin(), segments.end(), int64_t{0});
        EXPECT_LE(total, previous_total) << "at distance " << distance;
        previous_total = total;
    }
    EXPECT_EQ(segments.back(), 0) << "the farthest camera draws no strands";
    EXPECT_GT(segments.front(), 0) << "it draws the coarsest thick hairs";
}

TEST_F(ViewSelectionTest, BadArgumentsThrow) {
    ViewSelection view(*asset_, asset_->rest_geometry());
    EXPECT_THROW(view.indices(-1, DrawPrimitive::lines), Error);
    EXPECT_THROW(view.indices(view.level_count(), DrawPrimitive::lines), Error);
    LodGeometry foreign = asset_->rest_geometry();
    foreign.levels.pop_back();
    EXPECT_THROW(ViewSelection(*asset_, foreign), Error);
    std::vector<uint32_t> out;
    EXPECT_THROW(append_draw_indices(view.selection(), 0, 1, DrawPrimitive::lines, out), Error);
}

}  // namespace
}  // namespace hairlod
