#include "hairlod/lod/selection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "hairlod/core/error.h"
#include "hanging_hair.h"

namespace hairlod {
namespace {

StrandSet hanging_hair(size_t curves) { return testing::hanging_hair(curves, 10, 4); }

// Dollies along a fixed ray towards `target`.
Camera camera_at(float distance, glm::vec3 target = glm::vec3(0, 0, -0.3f)) {
    Camera camera;
    camera.view = glm::lookAt(target + distance * glm::normalize(glm::vec3(1.0f, 0.3f, 0.2f)), target, glm::vec3(0, 0, 1));
    camera.projection = glm::perspective(glm::radians(45.0f), 4.0f / 3.0f, 0.01f, 1000.0f);
    camera.viewport = {800.0f, 600.0f};
    return camera;
}

class SelectionTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        asset_ = new LodAsset(build_lod(hanging_hair(2000), {.guides = 16, .levels = 5, .control_points = 6, .seed = 1}));
        rest_ = new LodGeometry(asset_->rest_geometry());
    }
    static void TearDownTestSuite() {
        delete rest_;
        delete asset_;
    }
    static LodAsset* asset_;
    static LodGeometry* rest_;
};
LodAsset* SelectionTest::asset_ = nullptr;
LodGeometry* SelectionTest::rest_ = nullptr;

TEST(ProjectedWidth, OrthographicCorners) {
    // Identity matrices: NDC = world; a viewport of 100 px maps NDC 0.1 to 5 px.
    const std::array<glm::vec3, 4> corners{glm::vec3(0.1f, 0, 0.5f), glm::vec3(-0.1f, 0, -0.3f), glm::vec3(0, 0.05f, 0),
                                           glm::vec3(0, -0.05f, 0)};
    // The tangent is z: corners move onto the plane z = 0 before projection.
    EXPECT_NEAR(projected_width(glm::mat4(1.0f), {100.0f, 100.0f}, glm::vec3(0), {0, 0, 1}, corners), 10.0f, 1e-5f);
    const glm::mat4 behind = glm::perspective(1.0f, 1.0f, 0.1f, 10.0f);  // camera looks down -z
    EXPECT_TRUE(std::isinf(projected_width(behind, {100.0f, 100.0f}, glm::vec3(0, 0, 1), {1, 0, 0}, corners)));
}

TEST_F(SelectionTest, WidthBoundIsNeverBelowTheProjectedCornerWidth) {
    const glm::vec3 target(0, 0, -0.3f);
    for (const glm::vec3 direction : {glm::vec3(1.0f, 0.3f, 0.2f), glm::vec3(0.0f, 0.1f, 1.0f), glm::vec3(-0.2f, 1.0f, -0.6f)})
    for (float distance : {2.5f, 8.0f}) {
        Camera camera = camera_at(distance);
        camera.view = glm::lookAt(target + distance * glm::normalize(direction), target, glm::vec3(0.3f, 0.1f, 1.0f));
        const ScreenWidthBound bound(camera);
        const glm::mat4 view_projection = camera.projection * camera.view;
        for (size_t l = 0; l < rest_->levels.size(); ++l) {
            const ThickHairGeometry& g = rest_->levels[l];
            const auto nc = static_cast<size_t>(asset_->control_points);
            for (size_t c = 0; c < asset_->cluster_count(); ++c)
                for (int32_t h = asset_->thick_levels[l].cluster_first[c]; h < asset_->thick_levels[l].cluster_first[c + 1]; ++h)
                    for (size_t k = 0; k < nc; ++k) {
                        const size_t at = static_cast<size_t>(h) * nc + k;
                        const float exact = projected_width(view_projection, camera.viewport, g.centre[at], g.tangent[at], g.corners[at]);
                        const glm::vec4 widest = g.widest[c * nc + k];
                        // The cluster's widest diameter at the hair's own centre bounds the hair's width,
                        // and so does its ellipsoid, whatever the direction of view.
                        ASSERT_GE(bound(g.centre[at], widest.w), exact) << "level " << l << " hair " << h;
                        const float ellipsoid = bound.ellipsoid_width(g.centre[at], g.width_ellipsoid[c * nc + k]);
                        ASSERT_GE(ellipsoid, exact * (1.0f - 1e-5f)) << "level " << l << " hair " << h;
                        // The thinnest diameter rejects only what the ellipsoid rejects too.
                        ASSERT_LE(bound(g.centre[at], g.thinnest[c * nc + k]), ellipsoid) << "level " << l << " hair " << h;
                        ASSERT_EQ(bound.ellipsoid_fits(g.centre[at], g.width_ellipsoid[c * nc + k], exact),
                                  ellipsoid <= exact);
                        // The widest diameter that fits a width fits it, a little more does not.
                        const float fitting = bound.widest_fitting(g.centre[at], exact);
                        ASSERT_LE(bound(g.centre[at], fitting * (1.0f - 1e-5f)), exact);
                        ASSERT_GT(bound(g.centre[at], fitting * (1.0f + 1e-5f)), exact);
                    }
        }
    }
}

// Sec. 5.2's rule as the selection applies it: every thick hair drawn is at most eps_w wide on
// screen by the paper's corner measure (within the spread of depths inside a cluster, which the
// selection reads at its widest hair's depth), and the view-dependent bound draws thick hairs
// where the widest diameter alone would have drawn strands.
TEST_F(SelectionTest, DrawnThickHairsAreAtMostEpsWWideOnScreen) {
    const glm::vec3 target(0, 0, -0.3f);
    const auto nc = static_cast<size_t>(asset_->control_points);
    const int finest = static_cast<int>(asset_->thick_levels.size());
    float widest_ratio = 0.0f;
    int only_by_ellipsoid = 0;
    for (const glm::vec3 direction : {glm::vec3(1.0f, 0.3f, 0.2f), glm::vec3(0.0f, 0.1f, 1.0f), glm::vec3(-0.2f, 1.0f, -0.6f)})
        for (float distance : {3.0f, 8.0f, 20.0f}) {
            Camera camera = camera_at(distance);
            camera.view = glm::lookAt(target + distance * glm::normalize(direction), target, glm::vec3(0.3f, 0.1f, 1.0f));
            const ScreenWidthBound bound(camera);
            const glm::mat4 view_projection = camera.projection * camera.view;
            const Selection selection = select_initial(*asset_, *rest_, camera, 2.0f);
            for (size_t c = 0; c < asset_->cluster_count(); ++c) {
                if (!selection.visible[c]) continue;
                for (size_t s = 0; s + 1 < nc; ++s) {
                    const int level = selection.level[c * static_cast<size_t>(selection.segments) + s];
                    if (level >= finest) continue;
                    const ThickHairGeometry& g = rest_->levels[static_cast<size_t>(level)];
                    bool widest_fits = true;
                    for (size_t k : {s, s + 1}) {
                        const glm::vec4 widest = g.widest[c * nc + k];
                        widest_fits = widest_fits && bound(glm::vec3(widest), widest.w) <= 2.0f;
                        for (int32_t h = asset_->thick_levels[static_cast<size_t>(level)].cluster_first[c];
                             h < asset_->thick_levels[static_cast<size_t>(level)].cluster_first[c + 1]; ++h) {
                            const size_t at = static_cast<size_t>(h) * nc + k;
                            widest_ratio = std::max(widest_ratio, projected_width(view_projection, camera.viewport, g.centre[at],
                                                                                  g.tangent[at], g.corners[at]) / 2.0f);
                        }
                    }
                    if (!widest_fits) ++only_by_ellipsoid;
                }
            }
        }
    EXPECT_LE(widest_ratio, 1.02f);  // 0.988 measured
    EXPECT_GT(only_by_ellipsoid, 0);
}

TEST_F(SelectionTest, FartherCamerasNeverSelectFinerLevels) {
    Selection nearer = select_initial(*asset_, *rest_, camera_at(2.5f), 2.0f);
    int finest_seen = 0, coarsest_seen = 255;
    for (float distance : {4.0f, 8.0f, 16.0f, 40.0f, 120.0f}) {
        const Selection farther = select_initial(*asset_, *rest_, camera_at(distance), 2.0f);
        for (size_t i = 0; i < farther.level.size(); ++i) {
            const size_t cluster = i / static_cast<size_t>(farther.segments);
            if (!farther.visible[cluster] || !nearer.visible[cluster]) continue;
            ASSERT_LE(farther.level[i], nearer.level[i]) << "distance " << distance << " segment " << i;
            finest_seen = std::max<int>(finest_seen, nearer.level[i]);
            coarsest_seen = std::min<int>(coarsest_seen, farther.level[i]);
        }
        nearer = farther;
    }
    // The sweep exercises the hierarchy: fine levels near, L0 far.
    EXPECT_GE(finest_seen, 2);
    EXPECT_EQ(coarsest_seen, 0);
}

TEST_F(SelectionTest, Eq16ConvergesToTheInitialSelectionForAStaticCamera) {
    const int finest = static_cast<int>(asset_->thick_levels.size());
    for (float distance : {3.0f, 10.0f, 30.0f}) {
        const Camera camera = camera_at(distance);
        const Selection initial = select_initial(*asset_, *rest_, camera, 2.0f);
        EXPECT_EQ(select_deferred(*asset_, *rest_, camera, 2.0f, initial).level, initial.level) << distance;
        Selection from_coarsest = initial;
        std::fill(from_coarsest.level.begin(), from_coarsest.level.end(), 0);
        for (int frame = 0; frame <= finest; ++frame) from_coarsest = select_deferred(*asset_, *rest_, camera, 2.0f, from_coarsest);
        for (size_t i = 0; i < initial.level.size(); ++i)
            if (initial.visible[i / static_cast<size_t>(initial.segments)]) {
                ASSERT_EQ(from_coarsest.level[i], initial.level[i]) << distance;
            }
    }
}

// The calling thread alone (a viewport's update) selects what the pool does, levels and draws alike,
// initially and step by step.
TEST_F(SelectionTest, TheCallerThreadSelectsWhatThePoolSelects) {
    auto same = [](const Selection& a, const Selection& b, float distance) {
        EXPECT_EQ(a.level, b.level) << distance;
        EXPECT_EQ(a.visible, b.visible) << distance;
        ASSERT_EQ(a.draws.size(), b.draws.size()) << distance;
        for (size_t i = 0; i < a.draws.size(); ++i) {
            EXPECT_EQ(a.draws[i].level, b.draws[i].level);
            EXPECT_EQ(a.draws[i].cluster, b.draws[i].cluster);
            EXPECT_EQ(a.draws[i].first_segment, b.draws[i].first_segment);
            EXPECT_EQ(a.draws[i].segment_count, b.draws[i].segment_count);
        }
    };
    Selection pool = select_initial(*asset_, *rest_, camera_at(2.0f), 2.0f);
    Selection caller = select_initial(*asset_, *rest_, camera_at(2.0f), 2.0f, SelectionThreads::caller);
    same(pool, caller, 2.0f);
    for (float distance : {3.0f, 6.0f, 12.0f, 40.0f}) {
        select_deferred_in_place(*asset_, *rest_, camera_at(distance), 2.0f, pool, DeferredSteps::one);
        select_deferred_in_place(*asset_, *rest_, camera_at(distance), 2.0f, caller, DeferredSteps::one,
                                 SelectionThreads::caller);
        same(pool, caller, distance);
        EXPECT_FALSE(pool.draws.empty());
    }
}

TEST_F(SelectionTest, InitialSelectionIsTheCoarsestLevelWhosePointsFitPointByPoint) {
    // The selection measures a cluster's points in vector lanes; here each point is measured on its
    // own with ScreenWidthBound, by the rule the lanes restate: the widest hair fits, or the
    // ellipsoid does where the thinnest diameter can. Cameras from inside the hair to far away.
    const auto nc = static_cast<size_t>(asset_->control_points);
    const int finest = static_cast<int>(asset_->thick_levels.size());
    int cameras = 0, mixed = 0;
    for (const glm::vec3 target : {glm::vec3(0, 0, -0.3f), glm::vec3(0.2f, 0.1f, -0.6f)})
        for (float distance = 0.05f; distance < 400.0f; distance *= 1.3f, ++cameras) {
            const Camera camera = camera_at(distance, target);
            const ScreenWidthBound bound(camera);
            const auto point_fits = [&](int level, size_t at) {
                const ThickHairGeometry& g = rest_->levels[static_cast<size_t>(level)];
                const glm::vec3 centre(g.widest[at]);
                const float fitting = bound.widest_fitting(centre, 2.0f);
                return g.widest[at].w <= fitting ||
                       (!(g.thinnest[at] > fitting) && bound.ellipsoid_fits(centre, g.width_ellipsoid[at], 2.0f));
            };
            const Selection selection = select_initial(*asset_, *rest_, camera, 2.0f);
            std::set<int> levels;
            for (size_t c = 0; c < asset_->cluster_count(); ++c) {
                if (!selection.visible[c]) continue;
                for (size_t s = 0; s + 1 < nc; ++s) {
                    int expected = 0;
                    while (expected < finest && !(point_fits(expected, c * nc + s) && point_fits(expected, c * nc + s + 1))) ++expected;
                    ASSERT_EQ(selection.level[c * (nc - 1) + s], expected) << "distance " << distance << " cluster " << c;
                    levels.insert(expected);
                }
            }
            mixed += levels.size() > 1;
        }
    EXPECT_GT(cameras, 40);
    EXPECT_GT(mixed, 10);  // views where the levels differ between segments
}

TEST_F(SelectionTest, DrawsCoverEveryVisibleSegmentOnce) {
    const Selection selection = select_initial(*asset_, *rest_, camera_at(6.0f), 2.0f);
    std::vector<int> drawn(selection.level.size(), 0);
    for (const DrawRange& draw : selection.draws) {
        ASSERT_GT(draw.count, 0);
        for (int s = draw.first_segment; s < draw.first_segment + draw.segment_count; ++s) {
            const size_t at = static_cast<size_t>(draw.cluster * selection.segments + s);
            ++drawn[at];
            EXPECT_EQ(selection.level[at], draw.level);
        }
    }
    for (size_t i = 0; i < drawn.size(); ++i)
        EXPECT_EQ(drawn[i], selection.visible[i / static_cast<size_t>(selection.segments)] ? 1 : 0);
}

TEST_F(SelectionTest, CullsClustersOutsideTheFrustum) {
    Camera away = camera_at(5.0f);
    away.view = glm::lookAt(glm::vec3(5.0f, 0, 0), glm::vec3(10.0f, 0, 0), glm::vec3(0, 0, 1));  // facing away
    const Selection selection = select_initial(*asset_, *rest_, away, 2.0f);
    EXPECT_TRUE(selection.draws.empty());
    for (uint8_t v : selection.visible) EXPECT_EQ(v, 0);
    const Selection front = select_initial(*asset_, *rest_, camera_at(5.0f), 2.0f);
    EXPECT_GT(std::count(front.visible.begin(), front.visible.end(), 1), 0);
}

TEST_F(SelectionTest, RejectsBadArguments) {
    EXPECT_THROW(select_initial(*asset_, *rest_, camera_at(5.0f), 0.0f), Error);
    Selection wrong;
    EXPECT_THROW(select_deferred(*asset_, *rest_, camera_at(5.0f), 2.0f, wrong), Error);
}

}  // namespace
}  // namespace hairlod
