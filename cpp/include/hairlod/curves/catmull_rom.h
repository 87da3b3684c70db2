#pragma once
// Centripetal Catmull-Rom segments (knot spacing |p_{i+1} - p_i|^(1/2)), the curve that
// hair-meshes-realtime.txt Sec. 2.2 grows strands with: it interpolates its control points and
// never forms cusps or self-intersections within a segment.
#include <glm/vec3.hpp>
#include <array>
#include <cstddef>
#include <vector>

namespace hairlod {

class CatmullRomSegment {
public:
    // The segment runs from p1 (u = 0) to p2 (u = 1); p0 and p3 are its neighbours. A neighbour
    // that (nearly) coincides with its end point is replaced by the reflection of the other end,
    // so coincident control points never divide by zero.
    CatmullRomSegment(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                      const glm::vec3& p3);

    // Inline: strand generation evaluates millions of points per frame.
    glm::vec3 evaluate(float u) const {
        if (u <= 0.0f) return start_;
        if (u >= 1.0f) return end_;
        return evaluate_inside(u);
    }
    // The cubic without the end clamps, for u known to lie in [0, 1]: exact start at u = 0, the end
    // within float rounding at u = 1. Branch-free, so loops over many u vectorise.
    glm::vec3 evaluate_inside(float u) const { return start_ + ((a_ * u + b_) * u + c_) * u; }

    // The cubic's coefficients: p(u) = p1 + c1 u + c2 u^2 + c3 u^3, as {p1, c1, c2, c3}.
    std::array<glm::vec3, 4> polynomial() const { return {start_, c_, b_, a_}; }

    // The same segment from its knot intervals |p_{i+1} - p_i|^(1/2), when a caller has them
    // (neighbouring segments share two of their three).
    static CatmullRomSegment from_intervals(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                                            const glm::vec3& p3, double d01, double d12, double d23);

private:
    CatmullRomSegment() = default;

    // Cubic relative to the start, p(u) = p1 + ((a u + b) u + c) u: the coefficients are found in
    // double and stored as float offsets, so huge coordinates lose nothing beyond the rounding of
    // the float result itself while evaluation stays in single precision.
    glm::vec3 a_{0.0f}, b_{0.0f}, c_{0.0f};
    glm::vec3 start_, end_;
};

// The segment between control points i and i+1 of a polyline of `count` points, with the
// missing neighbours at the ends reflected (p_{-1} = 2 p_0 - p_1).
CatmullRomSegment curve_segment(const glm::vec3* points, size_t count, size_t i);

// All count - 1 segments of such a polyline (count >= 2), equal to curve_segment(points, count, i)
// for each i but with every knot interval computed once. Reuses the storage of `segments`.
void curve_segments(const glm::vec3* points, size_t count, std::vector<CatmullRomSegment>& segments);

}  // namespace hairlod
