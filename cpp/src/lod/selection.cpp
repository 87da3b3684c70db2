#include "hairlod/lod/selection.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hairlod/core/error.h"
#include "hairlod/core/vector_clones.h"

namespace hairlod {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Float `i` of the 6 at `entries` (a width ellipsoid's SymmetricEntries), through a 64-bit load of
// its pair: GCC vectorises loads in groups of 3 such pairs, and none in groups of 6 floats.
inline float entry(const float* entries, int i) {
    uint64_t pair;
    std::memcpy(&pair, entries + (i & ~1), sizeof pair);
    return std::bit_cast<float>(static_cast<uint32_t>(i & 1 ? pair >> 32 : pair));
}

// out[k] = 1 where control point k of `count` is at most width_px wide on screen (Context::measure
// says how), from its widest hair (`widest`, 4 floats each: centre and corner diameter), its thinnest
// diameter, its width ellipsoid (`ellipsoids`, 6 floats each) and the camera's terms
// (ScreenWidthBound::Terms). The arithmetic of ScreenWidthBound::widest_fitting and ellipsoid_fits,
// one lane per point, with no branches or calls (either kept GCC from vectorising the loop).
HAIRLOD_VECTOR_CLONES void fits_lanes(const float* __restrict widest, const float* __restrict thinnest,
                                      const float* __restrict ellipsoids, size_t count, const ScreenWidthBound::Terms& terms,
                                      float width_px, uint8_t* __restrict out) {
    const glm::vec4 depth = terms.depth_row;
    const float pixels_per_unit = terms.pixels_per_unit;
    for (size_t k = 0; k < count; ++k) {
        const float* point = widest + 4 * k;
        const float* e = ellipsoids + 6 * k;
        const float w = depth.x * point[0] + depth.y * point[1] + depth.z * point[2] + depth.w;
        const bool ahead = w > 0.0f;
        const float fitting = ahead ? width_px * w / pixels_per_unit : -1.0f;
        // B E B^T = [[x, z], [z, y]], summed in projected_form's order.
        float x = 0.0f, y = 0.0f, z = 0.0f;
        for (int i = 0; i < 6; ++i) {
            const float entry_i = entry(e, i);
            x += terms.form_rows[static_cast<size_t>(i)].x * entry_i;
            y += terms.form_rows[static_cast<size_t>(i)].y * entry_i;
            z += terms.form_rows[static_cast<size_t>(i)].z * entry_i;
        }
        const float half = 0.5f * width_px * w;
        const float t = half * half;
        const bool ellipsoid = ahead & (x <= t) & (y <= t) & ((t - x) * (t - y) >= z * z);
        // The widest hair fits, or the ellipsoid does where its thinnest diameter can.
        out[k] = static_cast<uint8_t>((point[3] <= fitting) | (!(thinnest[k] > fitting) & ellipsoid));
    }
}

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
    ScreenWidthBound::Terms terms = bound.terms();

    // out[k] = 1 where control point first + k (cluster c: c n_c + k) of a thick level is at most
    // width_px wide on screen, for `count` points at once. A point's width is the smaller of two
    // bounds of its hairs' Sec. 5.2 widths: the widest hair's diameter at the camera's largest
    // stretch, and the view-dependent ellipsoid of width_ellipsoid.h (fits_lanes).
    void measure(int level, size_t first, size_t count, uint8_t* out) const {
        const ThickHairGeometry& g = geometry.levels[static_cast<size_t>(level)];
        fits_lanes(&g.widest[first].x, &g.thinnest[first], g.width_ellipsoid[first].data(), count, terms, width_px, out);
    }
};

// Whether the segments of one cluster fit at each level: the strands always do; a thick level's
// segment where both its control points do. The first segment read at a level measures all the
// cluster's points there at once, in vector lanes (Context::measure); a cluster reads about two levels.
class ClusterFits {
public:
    explicit ClusterFits(const Context& context)
        : context_(context), points_(static_cast<size_t>(context.segments + 1)),
          fits_(static_cast<size_t>(context.finest) * points_) {}

    void start(size_t cluster) {
        cluster_ = cluster;
        measured_.fill(false);
    }

    bool fits(int level, size_t s) {
        if (level >= context_.finest) return true;
        const uint8_t* points = level_fits(level);
        return points[s] && points[s + 1];
    }

private:
    uint8_t* level_fits(int level) {
        const auto l = static_cast<size_t>(level);
        uint8_t* points = fits_.data() + l * points_;
        if (!measured_[l]) {
            measured_[l] = true;
            context_.measure(level, cluster_ * points_, points_, points);
        }
        return points;
    }

    const Context& context_;
    size_t points_;
    size_t cluster_ = 0;
    std::vector<uint8_t> fits_;               // [thick levels * n_c]: the current cluster's points
    std::array<bool, kMaxLevels> measured_{};  // per thick level: whether fits_ holds the cluster's
};

Context make_context(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px) {
    if (!(width_px > 0.0f)) throw Error("select: width_px must be > 0, got " + std::to_string(width_px));
    if (!(camera.viewport.x > 0.0f && camera.viewport.y > 0.0f)) throw Error("select: viewport size must be positive");
    if (geometry.levels.size() != asset.thick_levels.size() || geometry.cluster_bounds.size() != asset.cluster_count())
        throw Error("select: geometry does not belong to this asset");
    return {asset, geometry, Frustum(camera.projection * camera.view), ScreenWidthBound(camera), width_px,
            asset.control_points - 1, static_cast<int>(asset.thick_levels.size())};
}

// Marks each cluster visible or culled in `selection`, and calls body(c, fits) for each visible one
// with `fits` started on it. Clusters are selected independently: in the pool, in parallel over
// ranges that hold enough of them (tens of microseconds of work) that starting one costs little.
template <typename Body>
void for_visible_clusters(const Context& context, Selection& selection, SelectionThreads threads, const Body& body) {
    auto select_range = [&](size_t begin, size_t end) {
        ClusterFits fits(context);
        for (size_t c = begin; c != end; ++c) {
            selection.visible[c] = context.frustum.intersects(context.geometry.cluster_bounds[c]);
            if (!selection.visible[c]) continue;
            fits.start(c);
            body(c, fits);
        }
    };
    if (threads == SelectionThreads::caller) {
        select_range(0, context.asset.cluster_count());
        return;
    }
    constexpr size_t kClustersPerRange = 128;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, context.asset.cluster_count(), kClustersPerRange),
                      [&](const tbb::blocked_range<size_t>& range) { select_range(range.begin(), range.end()); });
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
    // x^T E x for x = x_row, y_row and the cross term, as dot products with E's six entries.
    const auto quadratic_form = [](const glm::vec3& p, const glm::vec3& q) {
        return std::array<float, 6>{p.x * q.x, p.y * q.y, p.z * q.z, p.x * q.y + p.y * q.x, p.y * q.z + p.z * q.y,
                                    p.z * q.x + p.x * q.z};
    };
    const std::array<float, 6> xx = quadratic_form(x_row, x_row), yy = quadratic_form(y_row, y_row),
                               xy = quadratic_form(x_row, y_row);
    for (int i = 0; i < 6; ++i) form_rows_[static_cast<size_t>(i)] = glm::vec3(xx[i], yy[i], xy[i]);
}

glm::vec3 ScreenWidthBound::projected_form(const SymmetricEntries& e) const {
    glm::vec3 form(0.0f);  // B E B^T = [[x, z], [z, y]]
    for (size_t i = 0; i < 6; ++i) form += form_rows_[i] * e[i];
    return form;
}

float ScreenWidthBound::ellipsoid_width(const glm::vec3& centre, const SymmetricEntries& e) const {
    const float w = depth_row_.x * centre.x + depth_row_.y * centre.y + depth_row_.z * centre.z + depth_row_.w;
    if (!(w > 0.0f)) return std::numeric_limits<float>::infinity();
    const glm::vec3 form = projected_form(e);
    const float half_gap = 0.5f * (form.x - form.y);
    const float largest = 0.5f * (form.x + form.y) + std::sqrt(half_gap * half_gap + form.z * form.z);
    return 2.0f * std::sqrt(std::max(largest, 0.0f)) / w;
}

bool ScreenWidthBound::ellipsoid_fits(const glm::vec3& centre, const SymmetricEntries& e, float width_px) const {
    const float w = depth_row_.x * centre.x + depth_row_.y * centre.y + depth_row_.z * centre.z + depth_row_.w;
    if (!(w > 0.0f)) return false;
    // 2 sqrt(lambda_max) / w <= width_px, without square roots: lambda_max <= t for the 2 x 2
    // matrix [[x, z], [z, y]] exactly when both diagonal entries are <= t and (t - x)(t - y) >= z^2.
    const float half = 0.5f * width_px * w;
    const float t = half * half;
    const glm::vec3 form = projected_form(e);
    return form.x <= t && form.y <= t && (t - form.x) * (t - form.y) >= form.z * form.z;
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

Selection select_initial(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px,
                         SelectionThreads threads) {
    const Context context = make_context(asset, geometry, camera, width_px);
    const auto segments = static_cast<size_t>(context.segments);
    Selection selection;
    selection.segments = context.segments;
    selection.level.assign(asset.cluster_count() * segments, 0);
    selection.visible.assign(asset.cluster_count(), 0);
    for_visible_clusters(context, selection, threads, [&](size_t c, ClusterFits& fits) {
        // Coarsest to finest; a segment takes the first level that is narrow enough.
        for (size_t s = 0; s < segments; ++s) {
            int level = 0;
            while (!fits.fits(level, s)) ++level;
            selection.level[c * segments + s] = static_cast<uint8_t>(level);
        }
    });
    collect_draws(context, selection);
    return selection;
}

void select_deferred_in_place(const LodAsset& asset, const LodGeometry& geometry, const Camera& camera, float width_px,
                              Selection& selection, DeferredSteps steps, SelectionThreads threads) {
    const Context context = make_context(asset, geometry, camera, width_px);
    const auto segments = static_cast<size_t>(context.segments);
    if (selection.segments != context.segments || selection.level.size() != asset.cluster_count() * segments ||
        selection.visible.size() != asset.cluster_count())
        throw Error("select: the previous selection does not belong to this asset");
    for_visible_clusters(context, selection, threads, [&](size_t c, ClusterFits& fits) {
        uint8_t* levels = selection.level.data() + c * segments;
        for (size_t s = 0; s < segments; ++s) {
            int level = std::min<int>(levels[s], context.finest);
            // Huang 2025 Eq. 16: w_cur > eps -> finer; w_cur- (one level coarser) <= eps -> coarser. Widths grow
            // with coarseness, so the steps go one way and stop at the coarsest level that fits.
            int direction = 0;
            if (!fits.fits(level, s)) direction = 1;
            else if (level > 0 && fits.fits(level - 1, s)) direction = -1;
            level += direction;
            if (steps == DeferredSteps::until_stable && direction > 0)
                while (!fits.fits(level, s)) ++level;
            else if (steps == DeferredSteps::until_stable && direction < 0)
                while (level > 0 && fits.fits(level - 1, s)) --level;
            levels[s] = static_cast<uint8_t>(level);
        }
    });
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
