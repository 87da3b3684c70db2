#include "hairlod/lod/width_ellipsoid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "hairlod/lod/selection.h"

namespace hairlod {
namespace {

glm::mat3 matrix_of(const SymmetricEntries& e) {
    return glm::mat3(e[0], e[3], e[5], e[3], e[1], e[4], e[5], e[4], e[2]);
}

glm::vec3 unit_normal_to(const glm::vec3& t, std::mt19937& rng) {
    std::normal_distribution<float> normal;
    const glm::vec3 r(normal(rng), normal(rng), normal(rng));
    return glm::normalize(r - glm::dot(r, t) * t);
}

// A camera looking at the origin from `direction`, 800 x 600 px.
Camera camera_from(const glm::vec3& direction, float distance) {
    Camera camera;
    const glm::vec3 up = std::abs(glm::normalize(direction).z) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
    camera.view = glm::lookAt(distance * glm::normalize(direction), glm::vec3(0.0f), up);
    camera.projection = glm::perspective(glm::radians(40.0f), 4.0f / 3.0f, 0.01f, 100.0f);
    camera.viewport = {800.0f, 600.0f};
    return camera;
}

// Sibling hairs: axes turned a little about a random tangent, radii up to 1.3x the widest's.
TEST(WidthEllipsoid, HoldsEverySemiAxisOfTheCluster) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int trial = 0; trial < 200; ++trial) {
        const glm::vec3 tangent = glm::normalize(glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, 1.0f));
        const glm::vec3 u = unit_normal_to(tangent, rng), v = glm::cross(tangent, u);
        const float a = 0.01f + uniform(rng), b = a * (trial % 10 == 0 ? 0.0f : uniform(rng));
        std::vector<glm::vec3> semi_axes;
        for (int h = 0; h < 6; ++h) {
            const float turn = 0.4f * (uniform(rng) - 0.5f), tilt = 0.2f * (uniform(rng) - 0.5f);
            const glm::vec3 major = (std::cos(turn) * u + std::sin(turn) * v + tilt * tangent) * a * (0.5f + 0.8f * uniform(rng));
            const glm::vec3 minor = (-std::sin(turn) * u + std::cos(turn) * v) * b * (0.5f + 0.8f * uniform(rng));
            semi_axes.push_back(major);
            semi_axes.push_back(minor);
        }
        const WidthEllipsoid ellipsoid = width_ellipsoid(tangent, a * u, b * v, semi_axes);
        const glm::mat3 inverse = glm::inverse(matrix_of(symmetric_entries(ellipsoid)));
        for (const glm::vec3& x : semi_axes) ASSERT_LE(glm::dot(x, inverse * x), 1.0f + 1e-3f) << "trial " << trial;
    }
}

// One hair alone: the bound is Sec. 5.2's corner width seen face-on and edge-on, and within sqrt(2)
// of it from any direction (the ellipse's widest projection against its projected semi-axes).
TEST(WidthEllipsoid, MatchesTheCornerWidthOfOneHairFromEveryDirection) {
    const glm::vec3 centre(0.0f), tangent(0, 0, 1), major(0.04f, 0, 0), minor(0, 0.015f, 0);
    const std::array<glm::vec3, 4> corners{major, -major, minor, -minor};
    const std::vector<glm::vec3> semi_axes{major, minor};
    const SymmetricEntries entries = symmetric_entries(width_ellipsoid(tangent, major, minor, semi_axes));
    const auto widths = [&](const glm::vec3& direction) {
        const Camera camera = camera_from(direction, 5.0f);
        const float exact = projected_width(camera.projection * camera.view, camera.viewport, centre, tangent, corners);
        return std::pair{ScreenWidthBound(camera).ellipsoid_width(centre, entries), exact};
    };
    const auto [face_on, face_on_exact] = widths(glm::vec3(0, 1, 0));   // looking down the minor axis
    const auto [edge_on, edge_on_exact] = widths(glm::vec3(1, 0, 0));   // down the major axis
    EXPECT_NEAR(face_on, face_on_exact, 1e-3f * face_on_exact);
    EXPECT_NEAR(edge_on, edge_on_exact, 1e-3f * edge_on_exact);
    EXPECT_NEAR(edge_on / face_on, 0.015f / 0.04f, 1e-3f);  // as thick as it is, not as wide
    std::mt19937 rng(5);
    std::normal_distribution<float> normal;
    for (int trial = 0; trial < 300; ++trial) {
        const glm::vec3 direction(normal(rng), normal(rng), normal(rng));
        if (std::abs(glm::normalize(direction).z) > 0.99f) continue;  // looking down the tangent: both are the ellipse
        const auto [bound, exact] = widths(direction);
        ASSERT_GE(bound, exact * (1.0f - 1e-5f)) << trial;
        ASSERT_LE(bound, std::sqrt(2.0f) * exact * (1.0f + 1e-4f)) << trial;
        // The test without square roots agrees with the width on either side of it.
        const ScreenWidthBound screen(camera_from(direction, 5.0f));
        ASSERT_TRUE(screen.ellipsoid_fits(centre, entries, bound * 1.001f)) << trial;
        ASSERT_FALSE(screen.ellipsoid_fits(centre, entries, bound * 0.999f)) << trial;
    }
}

TEST(WidthEllipsoid, AHairOfNoWidthHasNone) {
    const std::vector<glm::vec3> semi_axes{glm::vec3(0.0f), glm::vec3(0.0f)};
    const SymmetricEntries entries = symmetric_entries(width_ellipsoid({0, 0, 1}, glm::vec3(0.0f), glm::vec3(0.0f), semi_axes));
    for (float e : entries) EXPECT_EQ(e, 0.0f);
    EXPECT_EQ(ScreenWidthBound(camera_from({1, 0, 0}, 5.0f)).ellipsoid_width(glm::vec3(0.0f), entries), 0.0f);
    // Behind the camera nothing is narrow enough.
    EXPECT_TRUE(std::isinf(ScreenWidthBound(camera_from({1, 0, 0}, 5.0f)).ellipsoid_width(glm::vec3(10, 0, 0), entries)));
}

}  // namespace
}  // namespace hairlod
