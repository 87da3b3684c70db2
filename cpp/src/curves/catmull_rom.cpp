#include "hairlod/curves/catmull_rom.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace hairlod {

namespace {

// Intervals shorter than this fraction of the segment's own knot interval are treated as
// coincident points.
constexpr double kCoincidentFraction = 1e-6;

double knot_interval(const glm::dvec3& a, const glm::dvec3& b) {
    return std::sqrt(glm::length(b - a));
}

}  // namespace

CatmullRomSegment::CatmullRomSegment(const glm::vec3& p0_in, const glm::vec3& p1_in,
                                     const glm::vec3& p2_in, const glm::vec3& p3_in)
    : start_(p1_in), end_(p2_in) {
    glm::dvec3 p0(p0_in), p1(p1_in), p2(p2_in), p3(p3_in);
    const double d12 = knot_interval(p1, p2);
    if (d12 == 0.0) {
        d_ = p1;
        return;
    }
    double d01 = knot_interval(p0, p1), d23 = knot_interval(p2, p3);
    if (d01 <= kCoincidentFraction * d12) {
        p0 = 2.0 * p1 - p2;
        d01 = d12;
    }
    if (d23 <= kCoincidentFraction * d12) {
        p3 = 2.0 * p2 - p1;
        d23 = d12;
    }
    // Tangents of the non-uniform Catmull-Rom spline with knots t0 = -d01, t1 = 0, t2 = d12,
    // t3 = d12 + d23 (t1 at zero avoids cancellation), scaled to the unit parameter u.
    const glm::dvec3 m1 = ((p1 - p0) / d01 - (p2 - p0) / (d01 + d12) + (p2 - p1) / d12) * d12;
    const glm::dvec3 m2 = ((p2 - p1) / d12 - (p3 - p1) / (d12 + d23) + (p3 - p2) / d23) * d12;
    a_ = 2.0 * (p1 - p2) + m1 + m2;
    b_ = 3.0 * (p2 - p1) - 2.0 * m1 - m2;
    c_ = m1;
    d_ = p1;
}

glm::vec3 CatmullRomSegment::evaluate(float u) const {
    if (u <= 0.0f) return start_;
    if (u >= 1.0f) return end_;
    const double t = u;
    return glm::vec3(((a_ * t + b_) * t + c_) * t + d_);
}

CatmullRomSegment curve_segment(const glm::vec3* points, size_t count, size_t i) {
    const glm::vec3& p1 = points[i];
    const glm::vec3& p2 = points[i + 1];
    const glm::vec3 p0 = i > 0 ? points[i - 1] : 2.0f * p1 - p2;
    const glm::vec3 p3 = i + 2 < count ? points[i + 2] : 2.0f * p2 - p1;
    return CatmullRomSegment(p0, p1, p2, p3);
}

}  // namespace hairlod
