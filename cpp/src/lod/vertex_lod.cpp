#include "hairlod/lod/vertex_lod.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/core/error.h"

namespace hairlod {

namespace {

// Distance from `p` to the segment a-b, and where along it (t in [0, 1]) the nearest point lies.
float distance_to_chord(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, float& t) {
    const glm::vec3 chord = b - a, offset = p - a;
    const float length2 = glm::dot(chord, chord);
    t = length2 > 0.0f ? std::clamp(glm::dot(offset, chord) / length2, 0.0f, 1.0f) : 0.0f;
    return glm::length(offset - t * chord);
}

struct Curves {
    std::span<const float> points;
    std::span<const float> extents;
    size_t extent_size;
    std::vector<float> allowed;  // per point: the tolerance in world units at its depth

    glm::vec3 point(size_t i) const { return {points[3 * i], points[3 * i + 1], points[3 * i + 2]}; }

    // Whether every point strictly between `from` and `to` lies within its tolerance of the chord.
    bool chord_fits(size_t from, size_t to) const {
        const glm::vec3 a = point(from), b = point(to);
        for (size_t i = from + 1; i < to; ++i) {
            float t = 0.0f;
            const float off_chord = distance_to_chord(point(i), a, b, t);
            float off_extent2 = 0.0f;
            for (size_t k = 0; k < extent_size; ++k) {
                const float e0 = extents[from * extent_size + k], e1 = extents[to * extent_size + k];
                const float d = extents[i * extent_size + k] - (e0 + t * (e1 - e0));
                off_extent2 += d * d;
            }
            const float error = off_chord + std::sqrt(off_extent2);
            // A point with no tolerance (behind the camera) stays, even on the chord.
            if (!(error <= allowed[i]) || allowed[i] <= 0.0f) return false;
        }
        return true;
    }
};

}  // namespace

std::vector<uint8_t> vertex_lod_keep(std::span<const float> points, std::span<const int64_t> offsets,
                                     std::span<const float> extents, int extent_size, const Camera& camera,
                                     float tolerance_px) {
    if (!(tolerance_px >= 0.0f) || !std::isfinite(tolerance_px))
        throw Error("vertex LoD: tolerance_px must be >= 0 and finite, got " + std::to_string(tolerance_px));
    if (points.size() % 3 != 0) throw Error("vertex LoD: points must be [N, 3]");
    const size_t count = points.size() / 3;
    if (offsets.empty() || offsets.front() != 0 || static_cast<size_t>(offsets.back()) != count)
        throw Error("vertex LoD: offsets must run from 0 to the point count (" + std::to_string(count) + ")");
    for (size_t i = 1; i < offsets.size(); ++i)
        if (offsets[i] < offsets[i - 1]) throw Error("vertex LoD: offsets must not decrease");
    if (extent_size < 0 || extents.size() != count * static_cast<size_t>(extent_size))
        throw Error("vertex LoD: extents must hold extent_size values per point");

    std::vector<uint8_t> keep(count, 1);
    if (tolerance_px == 0.0f || count == 0) return keep;
    const ScreenWidthBound pixels_per_unit(camera);
    Curves curves{points, extents, static_cast<size_t>(extent_size), std::vector<float>(count)};
    tbb::parallel_for(size_t{0}, count, [&](size_t i) {
        // Zero behind the camera (an infinite bound): those points are all kept.
        curves.allowed[i] = tolerance_px / pixels_per_unit(curves.point(i), 1.0f);
    });
    tbb::parallel_for(size_t{0}, offsets.size() - 1, [&](size_t c) {
        const auto first = static_cast<size_t>(offsets[c]), end = static_cast<size_t>(offsets[c + 1]);
        if (end - first < 3) return;
        size_t kept = first;
        while (kept + 1 < end) {
            size_t next = kept + 1;
            while (next + 1 < end && curves.chord_fits(kept, next + 1)) ++next;
            for (size_t i = kept + 1; i < next; ++i) keep[i] = 0;
            kept = next;
        }
    });
    return keep;
}

std::vector<float> stride_chord_deviation(std::span<const float> points, int control_points,
                                          std::span<const int64_t> item_first, std::span<const int> strides) {
    if (control_points < 2) throw Error("stride deviation: control_points must be >= 2");
    const auto nc = static_cast<size_t>(control_points);
    if (points.size() % (3 * nc) != 0) throw Error("stride deviation: points must be [items * control_points, 3]");
    const size_t items = points.size() / (3 * nc);
    if (item_first.empty() || item_first.front() != 0 || static_cast<size_t>(item_first.back()) != items)
        throw Error("stride deviation: item_first must run from 0 to the item count (" + std::to_string(items) + ")");
    for (size_t g = 1; g < item_first.size(); ++g)
        if (item_first[g] < item_first[g - 1]) throw Error("stride deviation: item_first must not decrease");
    for (int s : strides)
        if (s < 1) throw Error("stride deviation: strides must be >= 1, got " + std::to_string(s));
    const size_t groups = item_first.size() - 1;
    std::vector<float> deviation(groups * strides.size(), 0.0f);
    auto point = [&](size_t i) { return glm::vec3(points[3 * i], points[3 * i + 1], points[3 * i + 2]); };
    tbb::parallel_for(size_t{0}, groups, [&](size_t g) {
        for (auto item = static_cast<size_t>(item_first[g]); item < static_cast<size_t>(item_first[g + 1]); ++item) {
            const size_t first = item * nc;
            for (size_t j = 0; j < strides.size(); ++j) {
                float& largest = deviation[g * strides.size() + j];
                const auto stride = static_cast<size_t>(strides[j]);
                for (size_t a = 0; a + 1 < nc; a += stride) {
                    const size_t b = std::min(a + stride, nc - 1);
                    for (size_t k = a + 1; k < b; ++k) {
                        float t = 0.0f;
                        const float d = distance_to_chord(point(first + k), point(first + a), point(first + b), t);
                        // NaN compares false: a point that is not finite makes the stride unusable.
                        largest = d <= largest ? largest : (std::isfinite(d) ? d : std::numeric_limits<float>::infinity());
                    }
                }
            }
        }
    });
    return deviation;
}

std::vector<int32_t> view_block_strides(std::span<const float> deviation, size_t stride_count,
                                        std::span<const glm::vec4> bounds, std::span<const int64_t> block_first,
                                        const Camera& camera, float tolerance_px) {
    if (!(tolerance_px >= 0.0f) || !std::isfinite(tolerance_px))
        throw Error("vertex LoD: tolerance_px must be >= 0 and finite, got " + std::to_string(tolerance_px));
    if (stride_count == 0 || deviation.size() != bounds.size() * stride_count)
        throw Error("vertex LoD: deviation must hold stride_count values per group of bounds");
    if (block_first.empty() || block_first.front() != 0 || static_cast<size_t>(block_first.back()) != bounds.size())
        throw Error("vertex LoD: block_first must run from 0 to the group count (" + std::to_string(bounds.size()) + ")");
    for (size_t b = 1; b < block_first.size(); ++b)
        if (block_first[b] < block_first[b - 1]) throw Error("vertex LoD: block_first must not decrease");
    const ScreenWidthBound pixels(camera);
    std::vector<int32_t> strides(block_first.size() - 1, 0);
    for (size_t b = 0; b + 1 < block_first.size(); ++b) {
        size_t longest = stride_count - 1;
        for (auto g = static_cast<size_t>(block_first[b]); g < static_cast<size_t>(block_first[b + 1]) && longest > 0; ++g) {
            const glm::vec4& sphere = bounds[g];
            // The deviation a tolerance of tolerance_px pixels allows there; 0 at the eye or for a sphere
            // that is not finite (NaN fails every comparison below).
            const float allowed = tolerance_px / pixels.at_nearest(glm::vec3(sphere), sphere.w, 1.0f);
            while (longest > 0 && !(deviation[g * stride_count + longest] <= allowed)) --longest;
        }
        strides[b] = static_cast<int32_t>(longest);
    }
    return strides;
}

}  // namespace hairlod
