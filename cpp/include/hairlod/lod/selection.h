#pragma once
// Screen-width LoD selection per L0 cluster and segment (hair-lod-aggregated-bcsdf.txt Sec. 5.1
// step 5 and Sec. 5.2): the initial selection and the deferred per-frame rule of Huang 2025 Eq. 16.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "hairlod/lod/lod_asset.h"

namespace hairlod {

// Column-major OpenGL / Blender matrices: clip = projection * view * world; NDC in [-1, 1]^3.
struct Camera {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::vec2 viewport{1.0f, 1.0f};  // pixels
};

// Segments [first_segment, first_segment + segment_count) of items [first, first + count) of one
// level: thick hairs of that level, or at the finest level positions in LodAsset::strand_order.
struct DrawRange {
    int32_t level = 0;
    int32_t cluster = 0;
    int32_t first = 0;
    int32_t count = 0;
    int32_t first_segment = 0;
    int32_t segment_count = 0;
};

struct Selection {
    int segments = 0;             // per hair: n_c - 1
    std::vector<uint8_t> level;   // [clusters * segments]; 0 = L0 (coarsest)
    std::vector<uint8_t> visible; // [clusters]: inside the view frustum
    std::vector<DrawRange> draws;
};

// The screen-width threshold eps_w (Sec. 5.1 step 5, Huang 2025 Eq. 16) in pixels: a cluster draws the coarsest
// level whose hairs are at most this wide on screen. Every tool's default (CLI, Python API, Blender
// panels) is this one, read through hairlod._core.
inline constexpr float kDefaultWidthPx = 2.0f;
// The smallest threshold the tools accept: at 0.01 px every visible cluster already draws its strands.
inline constexpr float kMinWidthPx = 0.01f;

// Projected width in pixels of one thick-hair cross-section (Sec. 5.2 "Hair width calculation"):
// the corners projected onto the plane through the centre normal to the tangent, then to the
// screen with the centre's perspective divide; the largest distance between them. Infinite when
// the centre is behind the camera.
float projected_width(const glm::mat4& view_projection, const glm::vec2& viewport, const glm::vec3& centre,
                      const glm::vec3& tangent, const std::array<glm::vec3, 4>& corners);

// An upper bound of the projected width (as projected_width measures it) of any cross-section
// whose in-plane corner diameter is `diameter` at `centre`: the diameter times the largest
// stretch of the camera's xy projection (the spectral norm of the viewport-scaled upper-left
// 2x3 block of projection * view) over the centre's clip w. Per camera a few flops per point, and
// never below the exact width, so a level it accepts is never wider than eps_w on screen.
class ScreenWidthBound {
public:
    explicit ScreenWidthBound(const Camera& camera);
    // Infinite when the centre is behind the camera.
    float operator()(const glm::vec3& centre, float diameter) const {
        const float w = depth_row_.x * centre.x + depth_row_.y * centre.y + depth_row_.z * centre.z + depth_row_.w;
        return w > 0.0f ? diameter * pixels_per_unit_ / w : std::numeric_limits<float>::infinity();
    }
    // The largest diameter at `centre` whose bound is at most width_px (one division for any
    // number of diameters); -1 when the centre is behind the camera, where nothing fits.
    float widest_fitting(const glm::vec3& centre, float width_px) const {
        const float w = depth_row_.x * centre.x + depth_row_.y * centre.y + depth_row_.z * centre.z + depth_row_.w;
        return w > 0.0f ? width_px * w / pixels_per_unit_ : -1.0f;
    }
    // The same at the nearest depth of the sphere (centre, radius): the most pixels `diameter` may
    // take anywhere in it. Infinite when the sphere reaches the eye.
    float at_nearest(const glm::vec3& centre, float radius, float diameter) const {
        const glm::vec3 gradient(depth_row_);
        const float w = depth_row_.x * centre.x + depth_row_.y * centre.y + depth_row_.z * centre.z + depth_row_.w -
                        radius * std::sqrt(gradient.x * gradient.x + gradient.y * gradient.y + gradient.z * gradient.z);
        return w > 0.0f ? diameter * pixels_per_unit_ / w : std::numeric_limits<float>::infinity();
    }

    // The per-camera terms the bounds are made of, for code that measures many points at once.
    struct Terms {
        glm::vec4 depth_row;    // row 3 of projection * view: clip w
        float pixels_per_unit;  // the largest stretch of the viewport-scaled xy rows
        std::array<glm::vec3, 6> form_rows;  // row i: what entry i of E adds to B E B^T's (x, y, z)
    };
    Terms terms() const { return {depth_row_, pixels_per_unit_, form_rows_}; }

    // The view-dependent bound (width_ellipsoid.h): 2 sqrt(lambda_max(B E B^T)) / w for the
    // ellipsoid with entries `e`, B the viewport-scaled xy rows of projection * view and w the
    // centre's clip w; the largest projected corner distance of any hair whose semi-axes it holds.
    // Infinite when the centre is behind the camera.
    float ellipsoid_width(const glm::vec3& centre, const SymmetricEntries& e) const;
    // ellipsoid_width(centre, e) <= width_px, decided without square roots.
    bool ellipsoid_fits(const glm::vec3& centre, const SymmetricEntries& e, float width_px) const;

private:
    glm::vec3 projected_form(const SymmetricEntries& e) const;  // (x, y, z): B E B^T = [[x, z], [z, y]]

    glm::vec4 depth_row_;  // row 3 of projection * view: clip w
    float pixels_per_unit_ = 0.0f;
    // Row i: what E's entry i adds to (x_row^T E x_row, y_row^T E y_row, x_row^T E y_row).
    std::array<glm::vec3, 6> form_rows_{};
};

// Where a selection's clusters are measured. In the pool (TBB), over ranges of clusters: fastest in a
// process of its own. In the calling thread alone: a viewport's per-frame update (ViewSelection) is a
// few hundred microseconds of work run inside the draw, where the GPU driver (llvmpipe rasterises
// on the same cores) and Blender's threads hold the cores; a pool thread descheduled there holds the
// whole update until it runs again. Inside Blender's draw (100k strands, 1347 L0 clusters, the dolly
// of scripts/bench_lod_preview.py) the update took a median of 0.24 ms in the calling thread against
// 0.32-0.36 ms in the pool, and 0.44-1.04 ms against 3.3-3.5 ms at the 90th percentile.
enum class SelectionThreads { pool, caller };

// Sec. 5.1 step 5: per visible cluster and segment, the coarsest level whose largest thick-hair
// width is at most width_px (the strands when none is). A control point's width is the smaller of
// ScreenWidthBound's two bounds (ThickHairGeometry::widest and width_ellipsoid), a segment's the
// larger of its two control points'.
Selection select_initial(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px,
                         SelectionThreads threads = SelectionThreads::pool);

// How far select_deferred_in_place moves a segment: one Huang 2025 Eq. 16 step (one level), or steps until
// Huang 2025 Eq. 16 changes nothing (the level a view that jumped needs, on its first frame).
enum class DeferredSteps { one, until_stable };

// Huang 2025 Eq. 16 per cluster and segment from the current levels in `selection`, updated in place (no
// array allocated once its draw list has grown to size; clusters measured where `threads` says): finer when the
// current level is too wide, coarser when one coarser level fits, else unchanged. Culled clusters
// keep their level.
void select_deferred_in_place(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px,
                              Selection& selection, DeferredSteps steps = DeferredSteps::one,
                              SelectionThreads threads = SelectionThreads::pool);

// Huang 2025 Eq. 16 from `previous`, returning the next selection.
Selection select_deferred(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px,
                          const Selection& previous);

// For benchmarks: the median seconds of one Huang 2025 Eq. 16 step (select_deferred_in_place) over `frames`
// steps from the initial selection, at a fixed camera (skinning excluded). frames >= 1.
double median_deferred_step_seconds(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera,
                                    float width_px, int frames);

}  // namespace hairlod
