#include "hairlod/hairmesh/styling_frames.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairlod/hairmesh/generate.h"
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

// Bhokare 2024 Eq. 1-3 on a skewed layer: the area-weighted mean of the corner maps, computed by hand.
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

// A polar cap of the unit sphere (the pole and two rings of `n` vertices at latitudes 60 and 30
// degrees), extruded radially into 3 layers, with latitude-longitude uv: u = segment / n (the seam
// closes at u = 1), v = latitude / 90 degrees. The uv of the pole corner of each triangle is
// `pole_uv(segment)`; around the pole, the uv directions of the faces turn a full circle.
template <class PoleUv>
HairMesh polar_cap(int n, PoleUv pole_uv) {
    constexpr float kPi = 3.14159265358979f;
    const std::array<float, 2> latitudes{kPi / 3.0f, kPi / 6.0f};
    std::vector<glm::vec3> root{glm::vec3(0, 0, 1)};
    for (float latitude : latitudes)
        for (int i = 0; i < n; ++i) {
            const float longitude = 2.0f * kPi * static_cast<float>(i) / static_cast<float>(n);
            root.emplace_back(std::cos(latitude) * std::cos(longitude), std::cos(latitude) * std::sin(longitude),
                              std::sin(latitude));
        }
    std::vector<glm::vec3> positions;
    for (int layer = 0; layer < 3; ++layer)
        for (const glm::vec3& p : root) positions.push_back(p * (1.0f + 0.3f * static_cast<float>(layer)));
    std::vector<int32_t> sizes, indices;
    std::vector<glm::vec2> uv;
    const auto ring = [n](int r, int i) { return 1 + r * n + i % n; };
    const auto ring_uv = [n, &latitudes](int r, int i) {
        return glm::vec2(static_cast<float>(i) / static_cast<float>(n), latitudes[r] / (3.14159265358979f / 2.0f));
    };
    for (int i = 0; i < n; ++i) {
        sizes.push_back(3);
        indices.insert(indices.end(), {0, ring(0, i), ring(0, i + 1)});
        uv.insert(uv.end(), {pole_uv(i), ring_uv(0, i), ring_uv(0, i + 1)});
    }
    for (int i = 0; i < n; ++i) {
        sizes.push_back(4);
        indices.insert(indices.end(), {ring(0, i), ring(1, i), ring(1, i + 1), ring(0, i + 1)});
        uv.insert(uv.end(), {ring_uv(0, i), ring_uv(1, i), ring_uv(1, i + 1), ring_uv(0, i + 1)});
    }
    return make_hair_mesh(std::move(positions), root.size(), sizes, indices, uv);
}

TEST(StylingFrames, RootUvWrappingAroundAPoleFallsBackToObjectSpace) {
    constexpr int n = 12;
    const float step = 1.0f / n;
    // Each triangle's own pole uv; one pole uv point for all; and pole uv equal to a ring corner's,
    // which collapses every pole triangle in uv.
    const std::vector<HairMesh> meshes{
        polar_cap(n, [step](int i) { return glm::vec2((static_cast<float>(i) + 0.5f) * step, 1.0f); }),
        polar_cap(n, [](int) { return glm::vec2(0.5f, 1.0f); }),
        polar_cap(n, [step](int i) { return glm::vec2(static_cast<float>(i) * step, 2.0f / 3.0f); }),
    };
    for (const HairMesh& mesh : meshes) {
        StylingFrames frames;
        ASSERT_NO_THROW(frames = compute_styling_frames(mesh));
        for (size_t at = 0; at < mesh.positions.size(); ++at) {
            ASSERT_TRUE(finite(frames.u[at]) && finite(frames.v[at])) << at;
            EXPECT_NEAR(glm::length(frames.u[at]), 1.0f, 1e-5f) << at;
            EXPECT_NEAR(glm::length(frames.v[at]), 1.0f, 1e-5f) << at;
            EXPECT_GT(glm::length(glm::cross(frames.u[at], frames.v[at])), 0.5f) << at;
        }
        // The pole (vertex 0, on every layer): a tangent frame with w = u x v along the normal +z.
        for (size_t layer = 0; layer < 3; ++layer) {
            const size_t at = layer * mesh.vertex_count;
            EXPECT_NEAR(frames.u[at].z, 0.0f, 1e-6f);
            EXPECT_GT(glm::cross(frames.u[at], frames.v[at]).z, 0.99f);
        }
        // The ring vertices keep the uv frame: u along the parallel (longitude direction).
        for (size_t i = 1; i < mesh.vertex_count; ++i) {
            const glm::vec3 p = mesh.position(0, i);
            const glm::vec3 east = glm::normalize(glm::vec3(-p.y, p.x, 0.0f));
            EXPECT_GT(glm::dot(frames.u[i], east), 0.95f) << i;
        }
        // Styled strands grow from it, finite, with roots on the cap.
        GenerateOptions options;
        options.count = 500;
        options.styling = {Curl{0.05f, 3.0f, 0.5f}, Twist{0.5f}, Clump{0.5f, 1.0f}, Frizz{0.01f, 5.0f}};
        const StrandSet strands = generate_strands(mesh, options);
        ASSERT_EQ(strands.curve_count(), 500u);
        for (const glm::vec3& p : strands.points) ASSERT_TRUE(finite(p));
        for (size_t c = 0; c < strands.curve_count(); ++c) {
            const glm::vec3& root = strands.points[static_cast<size_t>(strands.offsets[c])];
            EXPECT_GT(root.z, 0.4f);
            EXPECT_LE(glm::length(root), 1.0f + 1e-5f);
        }
    }
}

}  // namespace
}  // namespace hairlod
