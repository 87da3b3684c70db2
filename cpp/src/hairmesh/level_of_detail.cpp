#include "hairlod/hairmesh/level_of_detail.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairlod/hairmesh/tangents.h"

namespace hairlod {

namespace {

void check_level(float level) {
    if (!(level > 0.0f && level <= 1.0f))
        throw Error("level of detail must be in (0, 1], got " + std::to_string(level));
}

}  // namespace

float detail_level(float model_size, float resolution_px, float distance, float field_of_view, float alpha) {
    // tan(theta) must be positive: theta in (0, pi/2).
    if (!(distance > 0.0f) || !(field_of_view > 0.0f && field_of_view < 1.5707963f))
        throw Error("detail_level needs a positive distance and a field of view in (0, pi/2)");
    return std::min(1.0f, model_size * resolution_px / (distance * std::tan(field_of_view)) * alpha);
}

int64_t lod_strand_count(int64_t strands, float level, float delta) {
    check_level(level);
    const double count = std::ceil(static_cast<double>(level) * (static_cast<double>(strands) + delta));
    return std::min(strands, static_cast<int64_t>(count));
}

float thickness_compensation(int64_t strands, float level) {
    check_level(level);
    return std::min(1.0f / level, static_cast<float>(std::max<int64_t>(strands, 1)));
}

VertexLod vertex_lod(int max_segments, float level, float transition) {
    check_level(level);
    if (max_segments < 1 || !std::has_single_bit(static_cast<unsigned>(max_segments)))
        throw Error("vertex LoD needs 2^E segments, got " + std::to_string(max_segments));
    if (!(transition > 0.0f && transition <= 1.0f))
        throw Error("vertex LoD transition window must be in (0, 1], got " + std::to_string(transition));
    // log2(L n s) in double: E + log2(L), exact for L = 1.
    const double x = std::bit_width(static_cast<unsigned>(max_segments)) - 1 + std::log2(static_cast<double>(level));
    VertexLod lod;
    lod.exponent = std::max(0, static_cast<int>(std::ceil(x)));         // Bhokare 2024 Eq. 9
    const int next = std::max(0, static_cast<int>(std::ceil(x - transition)));  // Bhokare 2024 Eq. 10
    // Bhokare 2024 Eq. 12
    if (lod.exponent > next) lod.gamma = static_cast<float>(std::clamp(1.0 - (x - next) / transition, 0.0, 1.0));
    return lod;
}

void morph_vertex_lod(std::span<glm::vec3> points, std::span<glm::vec3> tangents, std::span<glm::vec3> coarse,
                      float gamma) {
    if (gamma <= 0.0f || points.size() < 3) return;
    coarse_strand_tangents(points, coarse);
    // Not renormalised: linear interpolation of the morphed tangents along the strand then matches
    // the coarser level exactly at gamma = 1 (renderers normalise per fragment anyway).
    for (size_t k = 0; k < points.size(); ++k) tangents[k] = (1.0f - gamma) * tangents[k] + gamma * coarse[k];
    for (size_t k = 1; k + 1 < points.size(); k += 2)  // Bhokare 2024 Eq. 11
        points[k] = (1.0f - gamma) * points[k] + gamma * 0.5f * (points[k - 1] + points[k + 1]);
}

}  // namespace hairlod
