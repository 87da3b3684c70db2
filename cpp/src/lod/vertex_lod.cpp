#include "hairlod/lod/vertex_lod.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/core/error.h"

namespace hairlod {

namespace {

struct Curves {
    std::span<const float> points;
    std::span<const float> extents;
    size_t extent_size;
    std::vector<float> allowed;  // per point: the tolerance in world units at its depth

    glm::vec3 point(size_t i) const { return {points[3 * i], points[3 * i + 1], points[3 * i + 2]}; }

    // Whether every point strictly between `from` and `to` lies within its tolerance of the chord.
    bool chord_fits(size_t from, size_t to) const {
        const glm::vec3 a = point(from), chord = point(to) - a;
        const float length2 = glm::dot(chord, chord);
        for (size_t i = from + 1; i < to; ++i) {
            const glm::vec3 offset = point(i) - a;
            const float t = length2 > 0.0f ? std::clamp(glm::dot(offset, chord) / length2, 0.0f, 1.0f) : 0.0f;
            float off_extent2 = 0.0f;
            for (size_t k = 0; k < extent_size; ++k) {
                const float e0 = extents[from * extent_size + k], e1 = extents[to * extent_size + k];
                const float d = extents[i * extent_size + k] - (e0 + t * (e1 - e0));
                off_extent2 += d * d;
            }
            const float error = glm::length(offset - t * chord) + std::sqrt(off_extent2);
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

}  // namespace hairlod
