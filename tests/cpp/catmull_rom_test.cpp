#include "hairlod/curves/catmull_rom.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

namespace hairlod {
namespace {

// Independent reference: the textbook Barry-Goldman form with knots starting at 0.
glm::dvec3 reference_centripetal(glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, glm::dvec3 p3, double u) {
    const double t0 = 0.0;
    const double t1 = t0 + std::sqrt(glm::distance(p0, p1));
    const double t2 = t1 + std::sqrt(glm::distance(p1, p2));
    const double t3 = t2 + std::sqrt(glm::distance(p2, p3));
    const double t = t1 + u * (t2 - t1);
    const auto lerp = [t](glm::dvec3 a, glm::dvec3 b, double ta, double tb) {
        return (tb - t) / (tb - ta) * a + (t - ta) / (tb - ta) * b;
    };
    const glm::dvec3 a1 = lerp(p0, p1, t0, t1), a2 = lerp(p1, p2, t1, t2), a3 = lerp(p2, p3, t2, t3);
    const glm::dvec3 b1 = lerp(a1, a2, t0, t2), b2 = lerp(a2, a3, t1, t3);
    return lerp(b1, b2, t1, t2);
}

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

TEST(CatmullRom, InterpolatesItsEndPoints) {
    const CatmullRomSegment segment({0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, 2});
    EXPECT_EQ(segment.evaluate(0.0f), glm::vec3(1, 2, 0));
    EXPECT_EQ(segment.evaluate(1.0f), glm::vec3(3, 1, 1));
}

TEST(CatmullRom, MatchesTextbookCentripetalForm) {
    const glm::vec3 p0{0, 0, 0}, p1{1, 2, 0}, p2{3, 1, 1}, p3{4, 4, 2};
    const CatmullRomSegment segment(p0, p1, p2, p3);
    for (int i = 0; i <= 10; ++i) {
        const double u = i / 10.0;
        const glm::dvec3 expected = reference_centripetal(p0, p1, p2, p3, u);
        const glm::vec3 actual = segment.evaluate(static_cast<float>(u));
        EXPECT_NEAR(glm::distance(glm::dvec3(actual), expected), 0.0, 1e-5) << "u = " << u;
    }
}

TEST(CatmullRom, EvenlySpacedCollinearPointsGiveTheLine) {
    const CatmullRomSegment segment({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0});
    for (float u : {0.25f, 0.5f, 0.75f}) {
        const glm::vec3 p = segment.evaluate(u);
        EXPECT_NEAR(p.x, 1.0f + u, 1e-6f);
        EXPECT_EQ(p.y, 0.0f);
    }
}

TEST(CatmullRom, CoincidentNeighboursStayFinite) {
    const glm::vec3 a{1, 1, 1}, b{2, 1, 1};
    for (const CatmullRomSegment& segment :
         {CatmullRomSegment(a, a, b, b), CatmullRomSegment(a + glm::vec3(1e-20f), a, b, b),
          CatmullRomSegment(a, a, a, a), CatmullRomSegment(a, a, a, b)}) {
        for (int i = 0; i <= 8; ++i) EXPECT_TRUE(finite(segment.evaluate(i / 8.0f)));
    }
    // With both neighbours coincident the reflected ones make the segment a straight line.
    const glm::vec3 middle = CatmullRomSegment(a, a, b, b).evaluate(0.5f);
    EXPECT_NEAR(middle.x, 1.5f, 1e-6f);
}

TEST(CatmullRom, HugeAndTinyCoordinates) {
    for (float scale : {1e-20f, 1e20f}) {
        const CatmullRomSegment segment(glm::vec3(0) * scale, glm::vec3(1, 0, 0) * scale,
                                        glm::vec3(1, 1, 0) * scale, glm::vec3(2, 1, 0) * scale);
        const glm::vec3 p = segment.evaluate(0.5f);
        EXPECT_TRUE(finite(p));
        EXPECT_GT(p.y / scale, 0.0f);
        EXPECT_LT(p.y / scale, 1.0f);
    }
}

TEST(CatmullRom, CurveSegmentReflectsMissingEnds) {
    const std::vector<glm::vec3> points{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    const glm::vec3 first = curve_segment(points.data(), points.size(), 0).evaluate(0.5f);
    const glm::vec3 last = curve_segment(points.data(), points.size(), 1).evaluate(0.5f);
    EXPECT_NEAR(first.x, 0.5f, 1e-6f);
    EXPECT_NEAR(last.x, 1.5f, 1e-6f);
}

TEST(CatmullRom, CurveSegmentsEqualSegmentBySegment) {
    // Shared knot intervals must not change a bit: coincident neighbours, a reversal, huge values.
    const std::vector<std::vector<glm::vec3>> polylines{
        {{0, 0, 0}, {1, 0, 0}},
        {{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, 2}, {4, 4, 2}, {5, 3, 1}},
        {{1, 1, 1}, {1, 1, 1}, {2, 0, 1}, {0, 0, 0}},
        {{1e20f, 0, 0}, {1e20f, 1e19f, 0}, {0, 3e19f, -1e20f}}};
    std::vector<CatmullRomSegment> segments;
    for (const auto& points : polylines) {
        curve_segments(points.data(), points.size(), segments);
        ASSERT_EQ(segments.size(), points.size() - 1);
        for (size_t i = 0; i + 1 < points.size(); ++i) {
            const CatmullRomSegment one = curve_segment(points.data(), points.size(), i);
            for (float u : {0.0f, 0.3f, 0.75f, 1.0f}) EXPECT_EQ(segments[i].evaluate(u), one.evaluate(u)) << i << " " << u;
        }
    }
}

TEST(CatmullRom, EvaluateInsideMatchesEvaluate) {
    const CatmullRomSegment segment({0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, 2});
    EXPECT_EQ(segment.evaluate_inside(0.0f), segment.evaluate(0.0f));  // the start exactly
    for (float u : {0.1f, 0.5f, 0.9f}) EXPECT_EQ(segment.evaluate_inside(u), segment.evaluate(u));
    EXPECT_LT(glm::distance(segment.evaluate_inside(1.0f), segment.evaluate(1.0f)), 1e-6f);
}

}  // namespace
}  // namespace hairlod
