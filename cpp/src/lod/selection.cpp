#include "hairlod/lod/selection.h"

#include <algorithm>
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
    glm::mat4 view_projection;
    glm::vec2 viewport;
    int segments;
    int finest;  // the strands' level
};

// Largest width per segment of the cluster at one thick level; a segment's width is the larger of
// its two control points' widths. Each control point measures the cluster's hair with the largest
// rest major radius there (ThickHairLevel::widest_hair), which keeps the cost at n_c projections
// per cluster and level instead of one per hair (Sec. 5.2 takes the maximum over all hairs with
// atomicMax on the GPU).
void segment_widths(const Context& context, int level, size_t cluster, std::vector<float>& widths) {
    const ThickHairLevel& hairs = context.asset.thick_levels[static_cast<size_t>(level)];
    const ThickHairGeometry& g = context.geometry.levels[static_cast<size_t>(level)];
    const auto nc = static_cast<size_t>(context.segments + 1);
    float previous = 0.0f;
    for (size_t k = 0; k < nc; ++k) {
        const size_t at = static_cast<size_t>(hairs.widest_hair[cluster * nc + k]) * nc + k;
        const float width = projected_width(context.view_projection, context.viewport, g.centre[at], g.tangent[at], g.corners[at]);
        if (k > 0) widths[k - 1] = std::max(previous, width);
        previous = width;
    }
}

Context make_context(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px) {
    if (!(width_px > 0.0f)) throw Error("select: width_px must be > 0, got " + std::to_string(width_px));
    if (!(camera.viewport.x > 0.0f && camera.viewport.y > 0.0f)) throw Error("select: viewport size must be positive");
    if (geometry.levels.size() != asset.thick_levels.size() || geometry.cluster_bounds.size() != asset.cluster_count())
        throw Error("select: geometry does not belong to this asset");
    return {asset, geometry, camera.projection * camera.view, camera.viewport, asset.control_points - 1,
            static_cast<int>(asset.thick_levels.size())};
}

// Runs of equal level within each visible cluster become draw ranges.
void collect_draws(const Context& context, Selection& selection) {
    const auto segments = static_cast<size_t>(context.segments);
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
                draw.first = context.asset.cluster_strand_first[c];
                draw.count = context.asset.cluster_strand_first[c + 1] - draw.first;
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

Selection empty_selection(const Context& context) {
    Selection selection;
    selection.segments = context.segments;
    selection.level.assign(context.asset.cluster_count() * static_cast<size_t>(context.segments), 0);
    selection.visible.assign(context.asset.cluster_count(), 0);
    return selection;
}

}  // namespace

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
    const Frustum frustum(context.view_projection);
    Selection selection = empty_selection(context);
    const auto segments = static_cast<size_t>(context.segments);
    std::vector<float> widths(segments);
    for (size_t c = 0; c < asset.cluster_count(); ++c) {
        selection.visible[c] = frustum.intersects(geometry.cluster_bounds[c]);
        if (!selection.visible[c]) continue;
        uint8_t* levels = selection.level.data() + c * segments;
        std::fill(levels, levels + segments, static_cast<uint8_t>(context.finest));
        size_t unresolved = segments;
        // Coarsest to finest; a segment takes the first level that is narrow enough.
        for (int l = 0; l < context.finest && unresolved > 0; ++l) {
            segment_widths(context, l, c, widths);
            for (size_t s = 0; s < segments; ++s)
                if (levels[s] == context.finest && widths[s] <= width_px) {
                    levels[s] = static_cast<uint8_t>(l);
                    --unresolved;
                }
        }
    }
    collect_draws(context, selection);
    return selection;
}

Selection select_deferred(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px,
                          const Selection& previous) {
    const Context context = make_context(asset, geometry, camera, width_px);
    const auto segments = static_cast<size_t>(context.segments);
    if (previous.segments != context.segments || previous.level.size() != asset.cluster_count() * segments)
        throw Error("select: the previous selection does not belong to this asset");
    const Frustum frustum(context.view_projection);
    Selection selection = empty_selection(context);
    selection.level = previous.level;
    // Widths per thick level, computed only for the levels some segment of the cluster needs.
    std::vector<std::vector<float>> widths(static_cast<size_t>(context.finest), std::vector<float>(segments));
    std::vector<uint8_t> computed(static_cast<size_t>(context.finest));
    auto width_at = [&](size_t c, int level, size_t s) {
        if (level >= context.finest) return 0.0f;  // the strands are always fine enough
        if (!computed[static_cast<size_t>(level)]) {
            segment_widths(context, level, c, widths[static_cast<size_t>(level)]);
            computed[static_cast<size_t>(level)] = 1;
        }
        return widths[static_cast<size_t>(level)][s];
    };
    for (size_t c = 0; c < asset.cluster_count(); ++c) {
        selection.visible[c] = frustum.intersects(geometry.cluster_bounds[c]);
        if (!selection.visible[c]) continue;
        std::fill(computed.begin(), computed.end(), 0);
        uint8_t* levels = selection.level.data() + c * segments;
        for (size_t s = 0; s < segments; ++s) {
            const int current = std::min<int>(levels[s], context.finest);
            // Eq. 16: w_cur > eps -> finer; w_cur- (one level coarser) <= eps -> coarser.
            if (width_at(c, current, s) > width_px)
                levels[s] = static_cast<uint8_t>(current + 1);
            else if (current > 0 && width_at(c, current - 1, s) <= width_px)
                levels[s] = static_cast<uint8_t>(current - 1);
            else
                levels[s] = static_cast<uint8_t>(current);
        }
    }
    collect_draws(context, selection);
    return selection;
}

}  // namespace hairlod
