#include "hairlod/lod/vertex_lod.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

constexpr float kPi = 3.14159265f;
constexpr float kViewport = 512.0f;
constexpr float kFovY = 0.5f;

// Looks down -z from (0, 0, distance) at the origin.
Camera camera_at(float distance) {
    Camera camera;
    camera.view = glm::lookAt(glm::vec3(0, 0, distance), glm::vec3(0), glm::vec3(0, 1, 0));
    camera.projection = glm::perspective(kFovY, 1.0f, 0.01f, 1000.0f);
    camera.viewport = {kViewport, kViewport};
    return camera;
}

// World length of one pixel at `depth` in front of camera_at's eye.
float pixel_at(float depth) { return 2.0f * depth * std::tan(kFovY / 2.0f) / kViewport; }

struct Curves {
    std::vector<float> points;
    std::vector<int64_t> offsets{0};
    void add(const std::vector<glm::vec3>& curve) {
        for (const glm::vec3& p : curve) points.insert(points.end(), {p.x, p.y, p.z});
        offsets.push_back(offsets.back() + static_cast<int64_t>(curve.size()));
    }
    glm::vec3 point(size_t i) const { return {points[3 * i], points[3 * i + 1], points[3 * i + 2]}; }
    std::vector<uint8_t> keep(const Camera& camera, float tolerance_px, const std::vector<float>& extents = {},
                              int extent_size = 0) const {
        return vertex_lod_keep(points, offsets, extents, extent_size, camera, tolerance_px);
    }
};

// A quarter circle of radius 1 in the z = 0 plane, bending towards the camera's depth as well.
std::vector<glm::vec3> arc(int n, float depth_bend = 0.0f) {
    std::vector<glm::vec3> curve;
    for (int i = 0; i < n; ++i) {
        const float a = 0.5f * kPi * static_cast<float>(i) / static_cast<float>(n - 1);
        curve.push_back({std::cos(a), std::sin(a), depth_bend * std::sin(2.0f * a)});
    }
    return curve;
}

float distance_to_segment(glm::vec3 p, glm::vec3 a, glm::vec3 b) {
    const glm::vec3 ab = b - a;
    const float t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
    return glm::distance(p, a + t * ab);
}

TEST(VertexLod, AStraightCurveKeepsItsEnds) {
    Curves curves;
    std::vector<glm::vec3> line;
    for (int i = 0; i < 16; ++i) line.push_back({-0.5f + 0.05f * static_cast<float>(i), 0.1f, 0.0f});
    curves.add(line);
    const std::vector<uint8_t> keep = curves.keep(camera_at(3.0f), 0.1f);
    ASSERT_EQ(keep.size(), 16u);
    for (size_t i = 0; i < keep.size(); ++i) EXPECT_EQ(keep[i], i == 0 || i + 1 == keep.size()) << i;
}

TEST(VertexLod, ZeroToleranceAndShortCurvesKeepEveryPoint) {
    Curves curves;
    curves.add(arc(16));
    curves.add({{0, 0, 0}, {0.1f, 0, 0}});
    curves.add({{0, 0, 0}});
    for (uint8_t k : curves.keep(camera_at(100.0f), 0.0f)) EXPECT_EQ(k, 1);
    const std::vector<uint8_t> keep = curves.keep(camera_at(100.0f), 1.0f);
    EXPECT_EQ(keep[16], 1);
    EXPECT_EQ(keep[17], 1);
    EXPECT_EQ(keep[18], 1);
}

// The guarantee, brute force: every point left out lies within the tolerance (a pixel at its own
// depth) of the chord between the kept points around it, in 3D; fewer points stay as the camera
// moves away, and a fine tolerance near the camera keeps them all.
TEST(VertexLod, LeftOutPointsLieWithinTheToleranceOfTheChord) {
    for (float bend : {0.0f, 0.6f}) {
        Curves curves;
        curves.add(arc(33, bend));
        size_t previous = std::numeric_limits<size_t>::max();
        for (float distance : {2.5f, 10.0f, 40.0f, 160.0f, 4000.0f}) {
            const float tolerance = 0.25f;
            const std::vector<uint8_t> keep = curves.keep(camera_at(distance), tolerance);
            ASSERT_EQ(keep.front(), 1);
            ASSERT_EQ(keep.back(), 1);
            size_t kept = 0, from = 0;
            for (size_t i = 1; i < keep.size(); ++i) {
                if (!keep[i]) continue;
                ++kept;
                for (size_t j = from + 1; j < i; ++j) {
                    const glm::vec3 p = curves.point(j);
                    EXPECT_LE(distance_to_segment(p, curves.point(from), curves.point(i)),
                              tolerance * pixel_at(distance - p.z) * 1.001f)
                        << "bend " << bend << " distance " << distance << " point " << j;
                }
                from = i;
            }
            EXPECT_LE(kept, previous) << "bend " << bend << " distance " << distance;
            previous = kept;
        }
        EXPECT_EQ(previous, 1u) << "4000 units away the arc lies within 0.17 px of its chord: one segment";
        const std::vector<uint8_t> near = curves.keep(camera_at(2.5f), 0.001f);
        for (uint8_t k : near) EXPECT_EQ(k, 1);
    }
}

// A bend towards the camera shows no offset on screen but changes the shape that shadow rays see:
// it is measured in 3D and kept.
TEST(VertexLod, ABendInDepthIsKept) {
    Curves curves;
    curves.add({{0, 0, 0}, {0, 0.1f, 0.05f}, {0, 0.2f, 0}});
    EXPECT_EQ(curves.keep(camera_at(3.0f), 0.5f)[1], 1);
    Curves flat;
    flat.add({{0, 0, 0}, {0, 0.1f, 0.0f}, {0, 0.2f, 0}});
    EXPECT_EQ(flat.keep(camera_at(3.0f), 0.5f)[1], 0);
}

TEST(VertexLod, ExtentsAwayFromTheirInterpolationAreKept) {
    Curves curves;
    curves.add({{0, 0, 0}, {0.1f, 0, 0}, {0.2f, 0, 0}});
    const float pixel = pixel_at(3.0f);
    // A radius bump of 2 px on the middle point at 0.5 px tolerance; a linear ramp is left out.
    EXPECT_EQ(curves.keep(camera_at(3.0f), 0.5f, {0.0f, 2.0f * pixel, 0.0f}, 1)[1], 1);
    EXPECT_EQ(curves.keep(camera_at(3.0f), 0.5f, {0.0f, 1.0f * pixel, 2.0f * pixel}, 1)[1], 0);
}

TEST(VertexLod, PointsBehindTheCameraAreKept) {
    Curves curves;
    std::vector<glm::vec3> line;
    for (int i = 0; i < 8; ++i) line.push_back({0.0f, 0.0f, 2.0f + static_cast<float>(i)});  // eye at z = 3
    curves.add(line);
    const std::vector<uint8_t> keep = curves.keep(camera_at(3.0f), 1.0f);
    for (size_t i = 1; i + 1 < keep.size(); ++i) EXPECT_EQ(keep[i], 1) << i;
}

// A point that is not finite has no distance to compare: it and its curve's points stay.
TEST(VertexLod, PointsThatAreNotFiniteAreKept) {
    Curves curves;
    std::vector<glm::vec3> line;
    for (int i = 0; i < 6; ++i) line.push_back({0.1f * static_cast<float>(i), 0.0f, 0.0f});
    line[3].y = std::numeric_limits<float>::quiet_NaN();
    curves.add(line);
    const std::vector<uint8_t> keep = curves.keep(camera_at(3.0f), 10.0f);
    EXPECT_EQ(keep[3], 1);
}

TEST(VertexLod, BadInputIsRefusedByName) {
    Curves curves;
    curves.add(arc(5));
    const Camera camera = camera_at(3.0f);
    EXPECT_THROW(curves.keep(camera, -1.0f), Error);
    EXPECT_THROW(curves.keep(camera, std::numeric_limits<float>::quiet_NaN()), Error);
    EXPECT_THROW(curves.keep(camera, std::numeric_limits<float>::infinity()), Error);
    EXPECT_THROW(curves.keep(camera, 0.1f, {1.0f, 2.0f}, 1), Error);  // 2 extents for 5 points
    EXPECT_THROW(vertex_lod_keep(curves.points, std::vector<int64_t>{0, 4}, {}, 0, camera, 0.1f), Error);
    EXPECT_THROW(vertex_lod_keep(curves.points, std::vector<int64_t>{0, 3, 2, 5}, {}, 0, camera, 0.1f), Error);
    EXPECT_THROW(vertex_lod_keep(std::vector<float>{1, 2}, std::vector<int64_t>{0}, {}, 0, camera, 0.1f), Error);
    try {
        curves.keep(camera, -1.0f);
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("tolerance_px"), std::string::npos);
    }
}

// Brute force: the drawn chords of every item at stride s (0, s, 2s, ..., last), and each point's
// distance from the chord spanning it.
TEST(StrideChordDeviation, MatchesEveryPointsDistanceFromItsChord) {
    const int nc = 16;
    Curves curves;  // three arcs in two groups: {arc, bent arc}, {small arc}
    curves.add(arc(nc));
    curves.add(arc(nc, 0.3f));
    std::vector<glm::vec3> small = arc(nc);
    for (glm::vec3& p : small) p *= 0.1f;
    curves.add(small);
    const std::vector<int64_t> groups{0, 2, 3};
    const std::vector<int> strides{1, 2, 4, 8, 16};
    const std::vector<float> deviation = stride_chord_deviation(curves.points, nc, groups, strides);
    ASSERT_EQ(deviation.size(), 2 * strides.size());
    for (size_t g = 0; g < 2; ++g) {
        for (size_t j = 0; j < strides.size(); ++j) {
            float expected = 0.0f;
            for (auto item = static_cast<size_t>(groups[g]); item < static_cast<size_t>(groups[g + 1]); ++item) {
                for (int k = 0; k < nc; ++k) {
                    const int a = k / strides[j] * strides[j], b = std::min(a + strides[j], nc - 1);
                    if (k == a || k == b) continue;
                    expected = std::max(expected, distance_to_segment(curves.point(item * nc + static_cast<size_t>(k)),
                                                                      curves.point(item * nc + static_cast<size_t>(a)),
                                                                      curves.point(item * nc + static_cast<size_t>(b))));
                }
            }
            EXPECT_NEAR(deviation[g * strides.size() + j], expected, 1e-6f) << "group " << g << " stride " << strides[j];
        }
        EXPECT_EQ(deviation[g * strides.size()], 0.0f);  // stride 1 draws every point
        for (size_t j = 1; j < strides.size(); ++j)  // longer chords of an arc stray further
            EXPECT_GT(deviation[g * strides.size() + j], deviation[g * strides.size() + j - 1]);
    }
    // The whole quarter circle as one chord: its middle lies 1 - cos(pi / 4) from it.
    EXPECT_NEAR(deviation[1 * strides.size() + 4], 0.1f * (1.0f - std::cos(kPi / 4.0f)), 2e-3f);
}

TEST(StrideChordDeviation, APointThatIsNotFiniteForbidsTheStridesSkippingIt) {
    Curves curves;
    std::vector<glm::vec3> line;
    for (int i = 0; i < 8; ++i) line.push_back({0.1f * static_cast<float>(i), 0.0f, 0.0f});
    line[3].y = std::numeric_limits<float>::quiet_NaN();
    curves.add(line);
    const std::vector<float> deviation = stride_chord_deviation(curves.points, 8, std::vector<int64_t>{0, 1}, std::vector<int>{1, 2, 4});
    EXPECT_EQ(deviation[0], 0.0f);
    EXPECT_TRUE(std::isinf(deviation[1]));
    EXPECT_TRUE(std::isinf(deviation[2]));
}

TEST(StrideChordDeviation, BadInputIsRefused) {
    Curves curves;
    curves.add(arc(4));
    EXPECT_THROW(stride_chord_deviation(curves.points, 4, std::vector<int64_t>{0, 1}, std::vector<int>{0}), Error);
    EXPECT_THROW(stride_chord_deviation(curves.points, 1, std::vector<int64_t>{0, 4}, std::vector<int>{1}), Error);
    EXPECT_THROW(stride_chord_deviation(curves.points, 4, std::vector<int64_t>{0, 2}, std::vector<int>{1}), Error);
    EXPECT_THROW(stride_chord_deviation(curves.points, 3, std::vector<int64_t>{0, 1}, std::vector<int>{1}), Error);
    EXPECT_THROW(stride_chord_deviation(curves.points, 4, std::vector<int64_t>{}, std::vector<int>{1}), Error);
}

TEST(ViewBlockStrides, LongestStrideEveryGroupOfTheBlockAllows) {
    const Camera camera = camera_at(10.0f);  // the eye at z = 10 looking at the origin
    // Groups at the origin (nearest depth 9), deviations in pixels there of 0 / 1 / 3 for strides 1, 2, 4.
    const float pixel = pixel_at(9.0f);
    const std::vector<float> deviation{0, 1 * pixel, 3 * pixel, 0, 0.5f * pixel, 1 * pixel};
    const std::vector<glm::vec4> bounds{{0, 0, 0, 1}, {0, 0, 0, 1}};
    EXPECT_EQ(view_block_strides(deviation, 3, bounds, std::vector<int64_t>{0, 1, 2}, camera, 2.0f), (std::vector<int32_t>{1, 2}));
    EXPECT_EQ(view_block_strides(deviation, 3, bounds, std::vector<int64_t>{0, 2}, camera, 2.0f), (std::vector<int32_t>{1}));
    EXPECT_EQ(view_block_strides(deviation, 3, bounds, std::vector<int64_t>{0, 2}, camera, 0.0f), (std::vector<int32_t>{0}));
    // A sphere reaching the eye keeps every point.
    const std::vector<glm::vec4> at_eye{{0, 0, 0, 1}, {0, 0, 9.5f, 1}};
    EXPECT_EQ(view_block_strides(deviation, 3, at_eye, std::vector<int64_t>{0, 1, 2}, camera, 100.0f), (std::vector<int32_t>{2, 0}));
    EXPECT_THROW(view_block_strides(deviation, 3, bounds, std::vector<int64_t>{0, 1}, camera, 1.0f), Error);
    EXPECT_THROW(view_block_strides(deviation, 4, bounds, std::vector<int64_t>{0, 2}, camera, 1.0f), Error);
    EXPECT_THROW(view_block_strides(deviation, 3, bounds, std::vector<int64_t>{0, 2}, camera, -1.0f), Error);
}

}  // namespace
}  // namespace hairlod
