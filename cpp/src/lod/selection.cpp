#include "hairlod/lod/selection.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "hairlod/core/error.h"

namespace hairlod {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Frustum {
    glm::vec4 planes[6];  // inside: dot(plane.xyz, p) + plane.w >= 0, xyz unit

    explicit Frustum(const glm::mat4& m) {
        // Gribb & Hartmann: plane rows of the clip matrix, row i = (m[0][i], m[1][i], m[2][i], m[3][i]).
        const glm::vec4 row[4] = {{m[0][0], m[1][0], m[2][0], m[3][0]},
                                  {m[0][1], m[1][1], m[2][1], m[3][1]},
                                  {m[0][2], m[1][2], m[2][2], m[3][2]},
                                  {m[0][3], m[1][3], m[2][3], m[3][3]}};
        for (int i = 0; i < 3; ++i) {
            planes[2 * i] = row[3] + row[i];
            planes[2 * i + 1] = row[3] - row[i];
        }
        for (glm::vec4& plane : planes) {
            const float length = glm::length(glm::vec3(plane));
            if (length > 0.0f) plane /= length;
        }
    }

    bool intersects(const glm::vec4& sphere) const {
        for (const glm::vec4& plane : planes)
            if (glm::dot(glm::vec3(plane), glm::vec3(sphere)) + plane.w < -sphere.w) return false;
        return true;
    }
};

struct Context {
    const LodAsset& asset;
    const LodGeometry& geometry;
    Frustum frustum;
    ScreenWidthBound bound;
    float width_px;
    int segments;
    int finest;  // the strands' level

    // Width of segment s of cluster c at a thick level: the larger bound of its two control points.
    float segment_width(size_t c, int level, size_t s) const {
        if (level >= finest) return 0.0f;  // the strands are always fine enough
        const glm::vec4* widest =
            geometry.levels[static_cast<size_t>(level)].widest.data() + c * static_cast<size_t>(segments + 1) + s;
        return std::max(bound(glm::vec3(widest[0]), widest[0].w), bound(glm::vec3(widest[1]), widest[1].w));
    }
};

Context make_context(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px) {
    if (!(width_px > 0.0f)) throw Error("select: width_px must be > 0, got " + std::to_string(width_px));
    if (!(camera.viewport.x > 0.0f && camera.viewport.y > 0.0f)) throw Error("select: viewport size must be positive");
    if (geometry.levels.size() != asset.thick_levels.size() || geometry.cluster_bounds.size() != asset.cluster_count())
        throw Error("select: geometry does not belong to this asset");
    return {asset, geometry, Frustum(camera.projection * camera.view), ScreenWidthBound(camera), width_px,
            asset.control_points - 1, static_cast<int>(asset.thick_levels.size())};
}

// Runs of equal level within each visible cluster become draw ranges.
void collect_draws(const Context& context, Selection& selection) {
    const auto segments = static_cast<size_t>(context.segments);
    selection.draws.clear();
    for (size_t c = 0; c < context.asset.cluster_count(); ++c) {
        if (!selection.visible[c]) continue;
        const uint8_t* levels = selection.level.data() + c * segments;
        for (size_t s = 0; s < segments;) {
            size_t end = s + 1;
            while (end < segments && levels[end] == levels[s]) ++end;
            DrawRange draw;
            draw.level = levels[s];
            draw.cluster = static_cast<int32_t>(c);
            if (draw.level == context.finest) {
                const auto [first, end] = context.asset.cluster_strands(c);
                draw.first = first;
                draw.count = end - first;
            } else {
                const ThickHairLevel& level = context.asset.thick_levels[static_cast<size_t>(draw.level)];
                draw.first = level.cluster_first[c];
                draw.count = level.cluster_first[c + 1] - draw.first;
            }
            draw.first_segment = static_cast<int32_t>(s);
            draw.segment_count = static_cast<int32_t>(end - s);
            selection.draws.push_back(draw);
            s = end;
        }
    }
}

}  // namespace

ScreenWidthBound::ScreenWidthBound(const Camera& camera) {
    const glm::mat4 m = camera.projection * camera.view;
    depth_row_ = {m[0][3], m[1][3], m[2][3], m[3][3]};
    // Rows 0 and 1 of the 3x3 block, scaled to pixels; the largest singular value of that 2x3
    // matrix B is the square root of the largest eigenvalue of B B^T (2x2, closed form).
    const glm::vec3 x_row = 0.5f * camera.viewport.x * glm::vec3(m[0][0], m[1][0], m[2][0]);
    const glm::vec3 y_row = 0.5f * camera.viewport.y * glm::vec3(m[0][1], m[1][1], m[2][1]);
    const double a = glm::dot(x_row, x_row), b = glm::dot(x_row, y_row), d = glm::dot(y_row, y_row);
    const double largest = 0.5 * (a + d + std::sqrt((a - d) * (a - d) + 4.0 * b * b));
    // Rounded up a little so the float bound stays above the float width.
    pixels_per_unit_ = static_cast<float>(std::sqrt(largest) * (1.0 + 1e-5));
}

float projected_width(const glm::mat4& view_projection, const glm::vec2& viewport, const glm::vec3& centre,
                      const glm::vec3& tangent, const std::array<glm::vec3, 4>& corners) {
    const glm::vec4 clip_centre = view_projection * glm::vec4(centre, 1.0f);
    if (!(clip_centre.w > 0.0f)) return kInfinity;
    // Offsets are projected with the perspective divide of the centre: the cross-section is tiny
    // next to its depth, and a width that only scales with 1 / depth makes a farther camera never
    // select a finer level.
    const glm::vec2 to_pixels = 0.5f * viewport / clip_centre.w;
    glm::vec2 screen[4];
    for (int i = 0; i < 4; ++i) {
        const glm::vec3 offset = corners[i] - centre;
        const glm::vec3 on_plane = offset - glm::dot(offset, tangent) * tangent;
        screen[i] = glm::vec2(view_projection * glm::vec4(on_plane, 0.0f)) * to_pixels;
    }
    float widest = 0.0f;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) widest = std::max(widest, glm::distance(screen[i], screen[j]));
    return widest;
}

Selection select_initial(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px) {
    const Context context = make_context(asset, geometry, camera, width_px);
    const auto segments = static_cast<size_t>(context.segments);
    Selection selection;
    selection.segments = context.segments;
    selection.level.assign(asset.cluster_count() * segments, 0);
    selection.visible.assign(asset.cluster_count(), 0);
    for (size_t c = 0; c < asset.cluster_count(); ++c) {
        selection.visible[c] = context.frustum.intersects(geometry.cluster_bounds[c]);
        if (!selection.visible[c]) continue;
        // Coarsest to finest; a segment takes the first level that is narrow enough.
        for (size_t s = 0; s < segments; ++s) {
            int level = 0;
            while (level < context.finest && context.segment_width(c, level, s) > width_px) ++level;
            selection.level[c * segments + s] = static_cast<uint8_t>(level);
        }
    }
    collect_draws(context, selection);
    return selection;
}

void select_deferred_in_place(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px,
                              Selection& selection, DeferredSteps steps) {
    const Context context = make_context(asset, geometry, camera, width_px);
    const auto segments = static_cast<size_t>(context.segments);
    if (selection.segments != context.segments || selection.level.size() != asset.cluster_count() * segments ||
        selection.visible.size() != asset.cluster_count())
        throw Error("select: the previous selection does not belong to this asset");
    for (size_t c = 0; c < asset.cluster_count(); ++c) {
        selection.visible[c] = context.frustum.intersects(geometry.cluster_bounds[c]);
        if (!selection.visible[c]) continue;
        uint8_t* levels = selection.level.data() + c * segments;
        for (size_t s = 0; s < segments; ++s) {
            int level = std::min<int>(levels[s], context.finest);
            // Huang 2025 Eq. 16: w_cur > eps -> finer; w_cur- (one level coarser) <= eps -> coarser. Widths grow
            // with coarseness, so the steps go one way and stop at the coarsest level that fits.
            int direction = 0;
            if (level < context.finest && context.segment_width(c, level, s) > width_px) direction = 1;
            else if (level > 0 && context.segment_width(c, level - 1, s) <= width_px) direction = -1;
            level += direction;
            if (steps == DeferredSteps::until_stable && direction > 0)
                while (level < context.finest && context.segment_width(c, level, s) > width_px) ++level;
            else if (steps == DeferredSteps::until_stable && direction < 0)
                while (level > 0 && context.segment_width(c, level - 1, s) <= width_px) --level;
            levels[s] = static_cast<uint8_t>(level);
        }
    }
    collect_draws(context, selection);
}

Selection select_deferred(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px,
                          const Selection& previous) {
    Selection next = previous;
    select_deferred_in_place(asset, geometry, camera, width_px, next);
    return next;
}

double median_deferred_step_seconds(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera,
                                    float width_px, int frames) {
    if (frames < 1) throw Error("frames must be >= 1");
    Selection selection = select_initial(asset, geometry, camera, width_px);
    std::vector<double> seconds(static_cast<size_t>(frames));
    for (double& s : seconds) {
        const auto start = std::chrono::steady_clock::now();
        select_deferred_in_place(asset, geometry, camera, width_px, selection);
        s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    std::nth_element(seconds.begin(), seconds.begin() + frames / 2, seconds.end());
    return seconds[static_cast<size_t>(frames / 2)];
}

}  // namespace hairlod
