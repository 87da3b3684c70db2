#pragma once
// The frame attached to the (up to) 3 guides of an L0 cluster at one control-point index, in which
// skinned points store their local coordinates (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 4).
// With 3 guides spanning a triangle it is the triangular prism: origin g0, axes (g1 - g0, g2 - g0,
// unit normal), so local (a, b, h) means the barycentric weights (1 - a - b, a, b) plus an offset h
// along the normal. Degenerate guide sets use an orthonormal frame at the guides' centroid. Either
// way the frame moves with the guides, so rigid motions of the guides reproduce points exactly.
#include <array>
#include <cstdint>
#include <span>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace hairlod {

enum class FrameKind : uint8_t {
    Prism,   // 3 guides span a well-shaped triangle
    Spread,  // x = guide tangent, y = the longest guide-to-guide vector (collinear guides)
    Bend,    // x = guide tangent, y = the guides' curvature (coincident, bent guides)
    World,   // x = guide tangent, y = the world axis least aligned with it (nothing else determines a
             // frame: rotations about a straight guide are invisible, so not rigid-exact)
};

// The guides of one L0 cluster: 1 to 3 curves of `control_points` points each.
struct GuideSet {
    const glm::vec3* curves[3] = {nullptr, nullptr, nullptr};
    int count = 0;
    int control_points = 0;
};

struct GuideFrame {
    glm::vec3 origin{0.0f};
    glm::mat3 axes{1.0f};  // point = origin + axes * local
};

// The set of the guides `guides` (indices, -1 padded) within guide_points ([guides * control_points]).
GuideSet guide_set(const std::array<int32_t, 3>& guides, const glm::vec3* guide_points, int control_points);

// The best-conditioned kind for the rest pose at control point k.
FrameKind choose_frame_kind(const GuideSet& guides, int k);

// The frame of the given kind at control point k (rest or deformed guides).
GuideFrame guide_frame(FrameKind kind, const GuideSet& guides, int k);

// deformed.axes * rest.axes^-1 (in double: prism axes need not be orthogonal; the identity for
// singular rest axes). A rest point p skins to deformed.origin + map * (p - rest.origin): the
// deformed frame at p's rest local coordinates. Rest vectors (cross-section axes) map alike.
glm::mat3 frame_map(const GuideFrame& rest, const GuideFrame& deformed);

}  // namespace hairlod
