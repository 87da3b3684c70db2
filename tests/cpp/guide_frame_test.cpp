#include "hairlod/lod/guide_frame.h"

#include <gtest/gtest.h>

#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace hairlod {
namespace {

constexpr int kPoints = 5;

std::vector<glm::vec3> curve(glm::vec3 root, glm::vec3 bend) {
    std::vector<glm::vec3> c;
    for (int i = 0; i < kPoints; ++i) c.push_back(root + glm::vec3(0, 0, -0.2f * i) + bend * float(i * i) * 0.01f);
    return c;
}

GuideSet set_of(const std::vector<std::vector<glm::vec3>>& curves) {
    GuideSet set;
    set.control_points = kPoints;
    for (const auto& c : curves) set.curves[set.count++] = c.data();
    return set;
}

std::vector<std::vector<glm::vec3>> moved(const std::vector<std::vector<glm::vec3>>& curves, const glm::mat4& m) {
    auto out = curves;
    for (auto& c : out)
        for (auto& p : c) p = glm::vec3(m * glm::vec4(p, 1.0f));
    return out;
}

glm::vec3 skin(const GuideFrame& rest, const GuideFrame& deformed, const glm::vec3& point) {
    return deformed.origin + frame_map(rest, deformed) * (point - rest.origin);
}

// A point stored in the rest frame lands on the rigidly moved point (1e-5 relative).
void expect_rigid_exact(const std::vector<std::vector<glm::vec3>>& rest, FrameKind expected) {
    const glm::mat4 motion = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(3, -2, 1)), 1.1f, glm::normalize(glm::vec3(1, 2, -1)));
    const auto deformed = moved(rest, motion);
    for (int k = 0; k < kPoints; ++k) {
        const FrameKind kind = choose_frame_kind(set_of(rest), k);
        EXPECT_EQ(kind, expected) << "k " << k;
        const glm::vec3 point = rest[0][k] + glm::vec3(0.03f, -0.05f, 0.02f);
        const GuideFrame rest_frame = guide_frame(kind, set_of(rest), k);
        EXPECT_LT(glm::distance(skin(rest_frame, rest_frame, point), point), 1e-5f);
        const glm::vec3 skinned = skin(rest_frame, guide_frame(kind, set_of(deformed), k), point);
        const glm::vec3 expected_point(motion * glm::vec4(point, 1.0f));
        EXPECT_LT(glm::distance(skinned, expected_point), 1e-5f * glm::length(expected_point)) << "k " << k;
    }
}

TEST(GuideFrame, PrismIsBarycentricPlusNormalOffset) {
    const std::vector<std::vector<glm::vec3>> guides{curve({0, 0, 0}, {}), curve({1, 0, 0}, {}), curve({0, 1, 0}, {})};
    const GuideFrame frame = guide_frame(FrameKind::Prism, set_of(guides), 2);
    // Barycentric weights (0.25, 0.25, 0.5) plus 0.1 along the normal: moving guide 1 within the
    // guides' plane moves the point by its weight times the move, and keeps the normal offset.
    const glm::vec3 point(0.25f, 0.5f, -0.4f + 0.1f), shift(0.2f, -0.4f, 0.0f);
    auto shifted = guides;
    for (glm::vec3& p : shifted[1]) p += shift;
    EXPECT_LT(glm::distance(skin(frame, guide_frame(FrameKind::Prism, set_of(shifted), 2), point), point + 0.25f * shift), 1e-6f);
    expect_rigid_exact(guides, FrameKind::Prism);
}

TEST(GuideFrame, CollinearGuidesUseTheirSpread) {
    expect_rigid_exact({curve({0, 0, 0}, {}), curve({1, 0, 0}, {}), curve({2, 0, 0}, {})}, FrameKind::Spread);
    expect_rigid_exact({curve({0, 0, 0}, {}), curve({0, 1, 0}, {})}, FrameKind::Spread);
}

TEST(GuideFrame, CoincidentBentGuidesUseTheirCurvature) {
    const auto bent = curve({0, 0, 0}, {1, 0.5f, 0});
    expect_rigid_exact({bent, bent, bent}, FrameKind::Bend);
    expect_rigid_exact({bent}, FrameKind::Bend);
}

TEST(GuideFrame, StraightLoneGuideFallsBackToWorldAxes) {
    const std::vector<std::vector<glm::vec3>> guides{curve({0, 0, 0}, {})};
    EXPECT_EQ(choose_frame_kind(set_of(guides), 1), FrameKind::World);
    const GuideFrame frame = guide_frame(FrameKind::World, set_of(guides), 1);
    const glm::vec3 point(0.3f, -0.1f, 0.2f);
    EXPECT_LT(glm::distance(skin(frame, frame, point), point), 1e-6f);
}

TEST(GuideFrame, FullyDegenerateGuideStaysFinite) {
    const std::vector<std::vector<glm::vec3>> guides{std::vector<glm::vec3>(kPoints, glm::vec3(1, 2, 3))};
    const GuideFrame frame = guide_frame(choose_frame_kind(set_of(guides), 0), set_of(guides), 0);
    const glm::vec3 skinned = skin(frame, frame, glm::vec3(1.5f, 2, 3));
    EXPECT_TRUE(std::isfinite(skinned.x) && std::isfinite(skinned.y) && std::isfinite(skinned.z));
    EXPECT_LT(glm::distance(skinned, glm::vec3(1.5f, 2, 3)), 1e-6f);
}

}  // namespace
}  // namespace hairlod
