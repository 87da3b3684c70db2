#include "hairlod/hairmesh/hair_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hairlod/core/error.h"
#include "hairmesh_fixtures.h"

namespace hairlod {
namespace {

std::vector<glm::vec3> two_layers(const std::vector<glm::vec3>& root) {
    std::vector<glm::vec3> positions = root;
    for (const glm::vec3& p : root) positions.push_back(p + glm::vec3(0, 0, 1));
    return positions;
}

const std::vector<glm::vec3> kHexagon{{2, 0, 0}, {1, 1.7f, 0}, {-1, 1.7f, 0}, {-2, 0, 0}, {-1, -1.7f, 0}, {1, -1.7f, 0}};

TEST(HairMesh, LargerPolygonsSplitIntoQuadsAndTriangles) {
    const std::vector<int32_t> hexagon_sizes{6}, hexagon{0, 1, 2, 3, 4, 5};
    const HairMesh six = make_hair_mesh(two_layers(kHexagon), 6, hexagon_sizes, hexagon);
    ASSERT_EQ(six.face_count(), 2u);
    EXPECT_EQ(six.face_size(0), 4u);
    EXPECT_EQ(six.face_size(1), 4u);
    const std::vector<int32_t> pentagon_sizes{5}, pentagon{0, 1, 2, 3, 4};
    const HairMesh five = make_hair_mesh(two_layers(kHexagon), 6, pentagon_sizes, pentagon);
    ASSERT_EQ(five.face_count(), 2u);
    EXPECT_EQ(five.face_size(0), 4u);
    EXPECT_EQ(five.face_size(1), 3u);
    // The split covers the polygon: areas add up (the hexagon is convex).
    EXPECT_NEAR(six.root_face_area(0) + six.root_face_area(1), 2 * 3.4 + 2 * 1.7 / 2 * 2, 1e-5);
}

TEST(HairMesh, UvIsSplitWithTheCorners) {
    const std::vector<int32_t> sizes{5}, pentagon{0, 1, 2, 3, 4};
    const std::vector<glm::vec2> uv{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}};
    const HairMesh mesh = make_hair_mesh(two_layers(kHexagon), 6, sizes, pentagon, uv);
    ASSERT_EQ(mesh.corner_uv.size(), 7u);
    EXPECT_EQ(mesh.corner_uv[4], glm::vec2(0, 0));  // second face starts at corner 0 of the polygon
    EXPECT_EQ(mesh.corner_uv[6], glm::vec2(4, 0));
}

TEST(HairMesh, TriangleCornersDuplicateTheLastVertex) {
    const HairMesh mesh = test::grid_hair_mesh(1, 1, 2, true);
    const FaceCorners corners = mesh.face_corners(0);
    EXPECT_TRUE(corners.triangle);
    EXPECT_EQ(corners.vertex[3], corners.vertex[2]);
    EXPECT_NEAR(mesh.root_face_area(0), 0.5, 1e-12);
}

TEST(HairMesh, BilinearWeightsSumToOne) {
    const auto w = bilinear_weights(0.3f, 0.8f);
    EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.0f, 1e-6f);
}

void expect_error(const std::function<void()>& build, const std::string& fragment) {
    try {
        build();
        FAIL() << "expected an error containing '" << fragment << "'";
    } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
    }
}

TEST(HairMesh, ValidationNamesTheProblem) {
    const std::vector<glm::vec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<int32_t> quad_size{4}, quad{0, 1, 2, 3}, repeated{0, 1, 1, 3}, outside{0, 1, 2, 9}, two{2};
    expect_error([&] { make_hair_mesh(square, 4, quad_size, quad); }, "at least one extrusion layer");
    expect_error([&] { make_hair_mesh({square.begin(), square.begin() + 3}, 4, quad_size, quad); }, "not a multiple");
    expect_error([&] { make_hair_mesh(two_layers(square), 4, quad_size, repeated); }, "appears twice");
    expect_error([&] { make_hair_mesh(two_layers(square), 4, quad_size, outside); }, "outside [0, 4)");
    expect_error([&] { make_hair_mesh(two_layers(square), 4, two, {quad.data(), 2}); }, "at least 3");
    expect_error([&] { make_hair_mesh(two_layers(square), 4, quad_size, {quad.data(), 3}); }, "need more vertex indices");
    auto with_nan = two_layers(square);
    with_nan[5].y = std::numeric_limits<float>::quiet_NaN();
    expect_error([&] { make_hair_mesh(with_nan, 4, quad_size, quad); }, "layer 1 vertex 1 is not finite");
    const std::vector<glm::vec2> short_uv{{0, 0}};
    expect_error([&] { make_hair_mesh(two_layers(square), 4, quad_size, quad, short_uv); }, "uv has 1 values");
    expect_error([&] { make_hair_mesh(two_layers(square), 4, quad_size, quad, {}, {0.0f}); }, "w has 1 values");
}

}  // namespace
}  // namespace hairlod
