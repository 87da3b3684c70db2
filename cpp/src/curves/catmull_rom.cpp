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

CatmullRomSegment::CatmullRomSegment(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                                     const glm::vec3& p3)
    : p0_(p0), p1_(p1), p2_(p2), p3_(p3) {
    d12_ = knot_interval(p1_, p2_);
    d01_ = knot_interval(p0_, p1_);
    d23_ = knot_interval(p2_, p3_);
    if (d01_ <= kCoincidentFraction * d12_) {
        p0_ = 2.0 * p1_ - p2_;
        d01_ = d12_;
    }
    if (d23_ <= kCoincidentFraction * d12_) {
        p3_ = 2.0 * p2_ - p1_;
        d23_ = d12_;
    }
}

glm::vec3 CatmullRomSegment::evaluate(float u) const {
    if (d12_ == 0.0 || u <= 0.0f) return glm::vec3(p1_);
    if (u >= 1.0f) return glm::vec3(p2_);
    // Barry-Goldman pyramid on the knots t0 = -d01, t1 = 0, t2 = d12, t3 = d12 + d23.
    const double t0 = -d01_, t1 = 0.0, t2 = d12_, t3 = d12_ + d23_;
    const double t = static_cast<double>(u) * d12_;
    const glm::dvec3 a1 = ((t1 - t) * p0_ + (t - t0) * p1_) / (t1 - t0);
    const glm::dvec3 a2 = ((t2 - t) * p1_ + (t - t1) * p2_) / (t2 - t1);
    const glm::dvec3 a3 = ((t3 - t) * p2_ + (t - t2) * p3_) / (t3 - t2);
    const glm::dvec3 b1 = ((t2 - t) * a1 + (t - t0) * a2) / (t2 - t0);
    const glm::dvec3 b2 = ((t3 - t) * a2 + (t - t1) * a3) / (t3 - t1);
    return glm::vec3(((t2 - t) * b1 + (t - t1) * b2) / (t2 - t1));
}

CatmullRomSegment curve_segment(const glm::vec3* points, size_t count, size_t i) {
    const glm::vec3& p1 = points[i];
    const glm::vec3& p2 = points[i + 1];
    const glm::vec3 p0 = i > 0 ? points[i - 1] : 2.0f * p1 - p2;
    const glm::vec3 p3 = i + 2 < count ? points[i + 2] : 2.0f * p2 - p1;
    return CatmullRomSegment(p0, p1, p2, p3);
}

}  // namespace hairlod
