#pragma once
// Centripetal Catmull-Rom segments (knot spacing |p_{i+1} - p_i|^(1/2)), the curve that
// hair-meshes-realtime.txt Sec. 2.2 grows strands with: it interpolates its control points and
// never forms cusps or self-intersections within a segment.
#include <glm/vec3.hpp>

namespace hairlod {

class CatmullRomSegment {
public:
    // The segment runs from p1 (u = 0) to p2 (u = 1); p0 and p3 are its neighbours. A neighbour
    // that (nearly) coincides with its end point is replaced by the reflection of the other end,
    // so coincident control points never divide by zero.
    CatmullRomSegment(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                      const glm::vec3& p3);

    glm::vec3 evaluate(float u) const;

private:
    // Cubic in Horner form, p(u) = ((a u + b) u + c) u + d, evaluated in double.
    glm::dvec3 a_{0.0}, b_{0.0}, c_{0.0}, d_{0.0};
    glm::vec3 start_, end_;
};

// The segment between control points i and i+1 of a polyline of `count` points, with the
// missing neighbours at the ends reflected (p_{-1} = 2 p_0 - p_1).
CatmullRomSegment curve_segment(const glm::vec3* points, size_t count, size_t i);

}  // namespace hairlod
