#include "hairlod/hairmesh/subdivision.h"

#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairlod/core/strand_metrics.h"
#include "hairmesh_fixtures.h"

namespace hairlod {
namespace {

TEST(Subdivision, CatmullClarkRefinesEveryLayerAlike) {
    const HairMesh mesh = test::grid_hair_mesh(2, 2, 3, false, 0.4f);
    for (int level = 1; level <= 3; ++level) {
        const HairMesh refined = subdivide_hair_mesh(mesh, level);
        EXPECT_EQ(refined.face_count(), mesh.face_count() << (2 * level));
        EXPECT_EQ(refined.layer_count(), mesh.layer_count());
        const size_t side = (2u << level) + 1;  // a 2x2 grid of quads becomes (2^(level+1))^2 quads
        EXPECT_EQ(refined.vertex_count, side * side);
        for (size_t f = 0; f < refined.face_count(); ++f) EXPECT_EQ(refined.face_size(f), 4u);
        // The flat root layer stays flat; each layer is a rigid copy of the root here, shifted.
        for (size_t layer = 0; layer < refined.layer_count(); ++layer)
            for (size_t i = 0; i < refined.vertex_count; ++i)
                EXPECT_NEAR(refined.position(layer, i).z, float(layer), 1e-5f);
    }
}

TEST(Subdivision, BoundaryCornersStayPut) {
    const HairMesh mesh = test::grid_hair_mesh(2, 2, 2);
    const HairMesh refined = subdivide_hair_mesh(mesh, 2);
    const Bounds3 before = bounding_box(mesh.positions), after = bounding_box(refined.positions);
    EXPECT_LT(glm::distance(before.lower, after.lower), 1e-5f);
    EXPECT_LT(glm::distance(before.upper, after.upper), 1e-5f);
}

TEST(Subdivision, LoopForAllTriangleMeshes) {
    const HairMesh refined = subdivide_hair_mesh(test::grid_hair_mesh(2, 2, 2, true), 1);
    EXPECT_EQ(refined.face_count(), 8u * 4u);
    for (size_t f = 0; f < refined.face_count(); ++f) EXPECT_EQ(refined.face_size(f), 3u);
}

TEST(Subdivision, UvAndWAreRefined) {
    HairMesh mesh = test::grid_hair_mesh(2, 1, 2);
    for (int32_t vertex : mesh.corner_vertices) mesh.corner_uv.emplace_back(glm::vec2(mesh.position(0, vertex)) * 0.5f);
    mesh.w.assign(mesh.positions.size(), 0.0f);
    for (size_t i = mesh.vertex_count; i < mesh.positions.size(); ++i) mesh.w[i] = 2.0f;
    const HairMesh refined = subdivide_hair_mesh(mesh, 2);
    ASSERT_EQ(refined.corner_uv.size(), refined.corner_count());
    ASSERT_EQ(refined.w.size(), refined.positions.size());
    // Linear face-varying uv: still half the root position of a flat, evenly refined grid.
    for (size_t k = 0; k < refined.corner_count(); ++k)
        EXPECT_LT(glm::distance(refined.corner_uv[k], 0.5f * glm::vec2(refined.position(0, refined.corner_vertices[k]))), 1e-4f);
    for (size_t i = 0; i < refined.vertex_count; ++i) EXPECT_NEAR(refined.w[refined.vertex_count + i], 2.0f, 1e-5f);
}

TEST(Subdivision, LevelZeroCopiesAndLevelFourIsAnError) {
    const HairMesh mesh = test::grid_hair_mesh(1, 1, 2);
    EXPECT_EQ(subdivide_hair_mesh(mesh, 0).positions, mesh.positions);
    EXPECT_THROW(subdivide_hair_mesh(mesh, 4), Error);
    EXPECT_THROW(subdivide_hair_mesh(mesh, -1), Error);
}

}  // namespace
}  // namespace hairlod
