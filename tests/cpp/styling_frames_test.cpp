#include "hairlod/hairmesh/styling_frames.h"

#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairmesh_fixtures.h"

namespace hairlod {
namespace {

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

TEST(StylingFrames, FollowTheUvAxesOfAFlatPatch) {
    HairMesh mesh = test::grid_hair_mesh(3, 2, 3, false, 0.0f);
    // uv = (y, x): u must follow object y and v object x, whatever the corner.
    mesh.corner_uv.clear();
    for (int32_t vertex : mesh.corner_vertices) {
        const glm::vec3& p = mesh.position(0, vertex);
        mesh.corner_uv.emplace_back(p.y, p.x);
    }
    const StylingFrames frames = compute_styling_frames(mesh);
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        EXPECT_LT(glm::distance(frames.u[i], glm::vec3(0, 1, 0)), 1e-6f);
        EXPECT_LT(glm::distance(frames.v[i], glm::vec3(1, 0, 0)), 1e-6f);
    }
}

TEST(StylingFrames, WIsPathLengthFromTheRoot) {
    const HairMesh mesh = test::grid_hair_mesh(2, 2, 4, false, 0.0f);
    const StylingFrames frames = compute_styling_frames(mesh);
    for (size_t layer = 0; layer < 4; ++layer)
        for (size_t i = 0; i < mesh.vertex_count; ++i) EXPECT_FLOAT_EQ(frames.w[layer * mesh.vertex_count + i], float(layer));
}

TEST(StylingFrames, DirectionsAreSharedAndUnit) {
    const HairMesh mesh = test::grid_hair_mesh(3, 3, 3, true, 0.5f);
    const StylingFrames frames = compute_styling_frames(mesh);
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(frames.u[i]), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::length(frames.v[i]), 1.0f, 1e-5f);
        EXPECT_GT(glm::length(glm::cross(frames.u[i], frames.v[i])), 0.1f);
    }
}

// Eq. 1-3 on a skewed layer: the area-weighted mean of the corner maps, computed by hand.
TEST(StylingFrames, AverageAreaWeightedCornerMaps) {
    HairMesh mesh = test::grid_hair_mesh(1, 1, 2, false, 0.0f);
    mesh.positions[mesh.vertex_count + 3] += glm::vec3(0.5f, 0, 0);  // layer 1, vertex (1, 1)
    mesh.corner_uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const StylingFrames frames = compute_styling_frames(mesh);
    // The face's corners are vertices (0, 1, 3, 2). Vertex 0 lies only in its corner triangle
    // (0, 1, 2) with uv edges (1, 0) and (0, 1): u = p1 - p0.
    EXPECT_LT(glm::distance(frames.u[mesh.vertex_count + 0], glm::vec3(1, 0, 0)), 1e-6f);
    // Vertex 1's corner triangle (1, 3, 0) has edges (p3 - p1, p0 - p1) with uv (0, 1) and (-1, 0):
    // u = -(p0 - p1) = (1, 0, 0), v = p3 - p1 = (0.5, 1, 0).
    EXPECT_LT(glm::distance(frames.v[mesh.vertex_count + 1], glm::normalize(glm::vec3(0.5f, 1, 0))), 1e-6f);
}

TEST(StylingFrames, CollapsedLayerKeepsTheDirectionsBelow) {
    HairMesh mesh = test::grid_hair_mesh(2, 1, 3, false, 0.0f);
    for (size_t i = 0; i < mesh.vertex_count; ++i) mesh.positions[2 * mesh.vertex_count + i] = glm::vec3(1, 0.5f, 5);
    const StylingFrames frames = compute_styling_frames(mesh);
    for (size_t i = 0; i < mesh.vertex_count; ++i) {
        ASSERT_TRUE(finite(frames.u[2 * mesh.vertex_count + i]));
        EXPECT_EQ(frames.u[2 * mesh.vertex_count + i], frames.u[mesh.vertex_count + i]);
    }
}

TEST(StylingFrames, ZeroAreaRootLayerIsAnError) {
    HairMesh mesh = test::grid_hair_mesh(2, 1, 2, false, 0.0f);
    for (size_t i = 0; i < mesh.vertex_count; ++i) mesh.positions[i] = glm::vec3(1, 2, 3);
    EXPECT_THROW(compute_styling_frames(mesh), Error);
}

}  // namespace
}  // namespace hairlod
