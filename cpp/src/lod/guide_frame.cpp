#include "hairlod/lod/guide_frame.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace hairlod {

namespace {

// A triangle whose area is below this fraction of its longest edge squared is treated as
// degenerate: its barycentric coordinates would amplify guide noise.
constexpr double kMinPrismShape = 1e-3;
// A direction shorter than this fraction of the local segment length is treated as zero.
constexpr double kMinDirection = 1e-4;

struct GuideGeometry {
    glm::dvec3 point[3];
    glm::dvec3 centroid{0.0};
    glm::dvec3 tangent{0.0};  // summed central differences, not normalised
    glm::dvec3 bend{0.0};     // summed second differences
    double segment = 0.0;     // mean guide segment length around k
};

GuideGeometry gather(const GuideSet& guides, int k) {
    GuideGeometry g;
    const int last = guides.control_points - 1;
    const int before = std::max(k - 1, 0), after = std::min(k + 1, last);
    // Second differences need an interior point; the ends use their neighbour's.
    const int middle = std::clamp(k, 1, std::max(last - 1, 1));
    for (int i = 0; i < guides.count; ++i) {
        const glm::vec3* curve = guides.curves[i];
        g.point[i] = glm::dvec3(curve[k]);
        g.centroid += g.point[i];
        const glm::dvec3 step = glm::dvec3(curve[after]) - glm::dvec3(curve[before]);
        g.tangent += step;
        g.segment += glm::length(step) / std::max(after - before, 1);
        if (last >= 2)
            g.bend += glm::dvec3(curve[middle + 1]) - 2.0 * glm::dvec3(curve[middle]) + glm::dvec3(curve[middle - 1]);
    }
    g.centroid /= static_cast<double>(guides.count);
    g.segment /= static_cast<double>(guides.count);
    return g;
}

glm::dvec3 unit_or_zero(const glm::dvec3& v) {
    const double length = glm::length(v);
    return length > 0.0 ? v / length : glm::dvec3(0.0);
}

// The longest vector between two guide points (pairs in a fixed order, so ties resolve alike in
// the rest and the deformed pose).
glm::dvec3 longest_spread(const GuideGeometry& g, int count) {
    glm::dvec3 best(0.0);
    for (int i = 0; i < count; ++i)
        for (int j = i + 1; j < count; ++j) {
            const glm::dvec3 edge = g.point[j] - g.point[i];
            if (glm::dot(edge, edge) > glm::dot(best, best)) best = edge;
        }
    return best;
}

glm::dvec3 across(const glm::dvec3& v, const glm::dvec3& unit_tangent) {
    return v - glm::dot(v, unit_tangent) * unit_tangent;
}

glm::dvec3 least_aligned_world_axis(const glm::dvec3& unit_tangent) {
    const glm::dvec3 a = glm::abs(unit_tangent);
    if (a.x <= a.y && a.x <= a.z) return {1, 0, 0};
    return a.y <= a.z ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
}

GuideFrame orthonormal_frame(const glm::dvec3& origin, glm::dvec3 x, const glm::dvec3& towards_y) {
    if (glm::dot(x, x) == 0.0) x = {1, 0, 0};
    glm::dvec3 y = unit_or_zero(across(towards_y, x));
    if (glm::dot(y, y) == 0.0) y = unit_or_zero(across(least_aligned_world_axis(x), x));
    GuideFrame frame;
    frame.origin = glm::vec3(origin);
    frame.axes = glm::mat3(glm::dmat3(x, y, glm::cross(x, y)));
    return frame;
}

}  // namespace

FrameKind choose_frame_kind(const GuideSet& guides, int k) {
    const GuideGeometry g = gather(guides, k);
    const double scale = std::max(g.segment, 1e-30);
    if (guides.count == 3) {
        const glm::dvec3 e1 = g.point[1] - g.point[0], e2 = g.point[2] - g.point[0];
        const double longest = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e2 - e1, e2 - e1)});
        if (longest > 0.0 && glm::length(glm::cross(e1, e2)) >= kMinPrismShape * longest) return FrameKind::Prism;
    }
    const glm::dvec3 tangent = unit_or_zero(g.tangent);
    const glm::dvec3 spread = longest_spread(g, guides.count);
    if (glm::length(across(spread, tangent)) > kMinDirection * std::max(scale, glm::length(spread)))
        return FrameKind::Spread;
    if (glm::length(across(g.bend, tangent)) > kMinDirection * scale) return FrameKind::Bend;
    return FrameKind::World;
}

GuideFrame guide_frame(FrameKind kind, const GuideSet& guides, int k) {
    const GuideGeometry g = gather(guides, k);
    const glm::dvec3 tangent = unit_or_zero(g.tangent);
    switch (kind) {
        case FrameKind::Prism: {
            const glm::dvec3 e1 = g.point[1] - g.point[0], e2 = g.point[2] - g.point[0];
            GuideFrame frame;
            frame.origin = glm::vec3(g.point[0]);
            frame.axes = glm::mat3(glm::dmat3(e1, e2, unit_or_zero(glm::cross(e1, e2))));
            return frame;
        }
        case FrameKind::Spread: return orthonormal_frame(g.centroid, tangent, longest_spread(g, guides.count));
        case FrameKind::Bend: return orthonormal_frame(g.centroid, tangent, g.bend);
        case FrameKind::World: break;
    }
    return orthonormal_frame(g.centroid, tangent, least_aligned_world_axis(tangent));
}

glm::mat3 frame_map(const GuideFrame& rest, const GuideFrame& deformed) {
    const glm::dmat3 rest_axes(rest.axes);
    if (glm::determinant(rest_axes) == 0.0) return glm::mat3(1.0f);
    return glm::mat3(glm::dmat3(deformed.axes) * glm::inverse(rest_axes));
}

GuideSet guide_set(const std::array<int32_t, 3>& guides, const glm::vec3* guide_points, int control_points) {
    GuideSet set;
    set.control_points = control_points;
    for (int32_t g : guides)
        if (g >= 0) set.curves[set.count++] = guide_points + static_cast<size_t>(g) * control_points;
    return set;
}

}  // namespace hairlod
