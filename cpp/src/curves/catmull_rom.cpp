#include "hairlod/curves/catmull_rom.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace hairlod {

namespace {

// Intervals shorter than this fraction of the segment's own knot interval are treated as
// coincident points.
constexpr double kCoincidentFraction = 1e-6;

double knot_interval(const glm::vec3& a, const glm::vec3& b) {
    return std::sqrt(glm::length(glm::dvec3(b) - glm::dvec3(a)));
}

}  // namespace

CatmullRomSegment::CatmullRomSegment(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                                     const glm::vec3& p3)
    : CatmullRomSegment(from_intervals(p0, p1, p2, p3, knot_interval(p0, p1), knot_interval(p1, p2),
                                       knot_interval(p2, p3))) {}

CatmullRomSegment CatmullRomSegment::from_intervals(const glm::vec3& p0_in, const glm::vec3& p1_in,
                                                    const glm::vec3& p2_in, const glm::vec3& p3_in, double d01,
                                                    double d12, double d23) {
    CatmullRomSegment segment;
    segment.start_ = p1_in;
    segment.end_ = p2_in;
    if (d12 == 0.0) return segment;
    glm::dvec3 p0(p0_in), p1(p1_in), p2(p2_in), p3(p3_in);
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
    // Reciprocals once: five divisions instead of eighteen.
    const double inverse01 = 1.0 / d01, inverse12 = 1.0 / d12, inverse23 = 1.0 / d23;
    const double inverse02 = 1.0 / (d01 + d12), inverse13 = 1.0 / (d12 + d23);
    const glm::dvec3 m1 = ((p1 - p0) * inverse01 - (p2 - p0) * inverse02 + (p2 - p1) * inverse12) * d12;
    const glm::dvec3 m2 = ((p2 - p1) * inverse12 - (p3 - p1) * inverse13 + (p3 - p2) * inverse23) * d12;
    segment.a_ = glm::vec3(2.0 * (p1 - p2) + m1 + m2);
    segment.b_ = glm::vec3(3.0 * (p2 - p1) - 2.0 * m1 - m2);
    segment.c_ = glm::vec3(m1);
    return segment;
}

CatmullRomSegment curve_segment(const glm::vec3* points, size_t count, size_t i) {
    const glm::vec3& p1 = points[i];
    const glm::vec3& p2 = points[i + 1];
    const glm::vec3 p0 = i > 0 ? points[i - 1] : 2.0f * p1 - p2;
    const glm::vec3 p3 = i + 2 < count ? points[i + 2] : 2.0f * p2 - p1;
    return CatmullRomSegment(p0, p1, p2, p3);
}

void curve_segments(const glm::vec3* points, size_t count, std::vector<CatmullRomSegment>& segments) {
    segments.clear();
    if (count < 2) return;
    // Padded with the reflected end points; interval j lies between padded points j and j + 1.
    const glm::vec3 before = 2.0f * points[0] - points[1], after = 2.0f * points[count - 1] - points[count - 2];
    const auto padded = [&](size_t j) { return j == 0 ? before : j == count + 1 ? after : points[j - 1]; };
    double previous = knot_interval(padded(0), padded(1)), current = knot_interval(padded(1), padded(2));
    for (size_t i = 0; i + 1 < count; ++i) {
        const double next = knot_interval(padded(i + 2), padded(i + 3));
        segments.push_back(CatmullRomSegment::from_intervals(padded(i), padded(i + 1), padded(i + 2), padded(i + 3),
                                                             previous, current, next));
        previous = current;
        current = next;
    }
}

}  // namespace hairlod
