#include "hairlod/lod/preview_vertices.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "hanging_hair.h"

namespace hairlod {
namespace {

constexpr int kControlPoints = 6;

TEST(PolylineTangent, CentralInsideOneSidedAtTheEnds) {
    const glm::vec3 points[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 2}};
    EXPECT_EQ(polyline_tangent(points, 4, 0), glm::vec3(1, 0, 0));
    const glm::vec3 middle = polyline_tangent(points, 4, 1);
    EXPECT_NEAR(middle.x, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(middle.y, std::sqrt(0.5f), 1e-6f);
    EXPECT_EQ(polyline_tangent(points, 4, 3), glm::vec3(0, 0, 1));
}

TEST(PolylineTangent, AStretchWithoutLengthGetsAFixedUnitTangent) {
    const glm::vec3 still[] = {{2, 3, 4}, {2, 3, 4}, {2, 3, 4}};
    for (size_t k = 0; k < 3; ++k) EXPECT_EQ(polyline_tangent(still, 3, k), glm::vec3(0, 0, 1));
    // Tiny but not zero: still a unit direction, not the fallback.
    const glm::vec3 short_steps[] = {{0, 0, 0}, {0, 1e-12f, 0}};
    EXPECT_NEAR(glm::distance(polyline_tangent(short_steps, 2, 0), glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    // Coordinates that are not finite stay visible as NaN rather than a made-up direction.
    const float inf = std::numeric_limits<float>::infinity();
    const glm::vec3 broken[] = {{0, 0, 0}, {inf, 0, 0}};
    EXPECT_FALSE(std::isfinite(glm::length(polyline_tangent(broken, 2, 0))));
}

TEST(PreviewVertices, MatchTheRestGeometryInTheDrawingLayout) {
    const LodAsset asset = build_lod(testing::hanging_hair(600, 9, 5),
                                     {.guides = 12, .levels = 4, .control_points = kControlPoints, .seed = 3});
    const LodGeometry rest = asset.rest_geometry();
    const PreviewVertices vertices = preview_vertices(asset);
    const auto nc = static_cast<size_t>(kControlPoints);
    ASSERT_EQ(vertices.levels.size(), asset.thick_levels.size());
    for (size_t l = 0; l < asset.thick_levels.size(); ++l) {
        const ThickHairLevel& level = asset.thick_levels[l];
        const ThickStripVertices& v = vertices.levels[l];
        const std::vector<float> density = asset.density(l);
        ASSERT_EQ(v.position.size(), 2 * level.hair_count() * nc);
        for (size_t c = 0; c < asset.cluster_count(); ++c)
            for (auto h = static_cast<size_t>(level.cluster_first[c]); h < static_cast<size_t>(level.cluster_first[c + 1]); ++h)
                for (size_t k = 0; k < nc; ++k)
                    for (size_t side = 0; side < 2; ++side) {
                        const size_t at = 2 * (h * nc + k) + side, point = h * nc + k;
                        ASSERT_EQ(v.position[at], rest.levels[l].centre[point]);
                        ASSERT_EQ(v.tangent[at], rest.levels[l].tangent[point]);
                        ASSERT_EQ(v.major[at], rest.levels[l].major[point]);
                        ASSERT_EQ(v.minor[at], rest.levels[l].minor[point]);
                        ASSERT_EQ(v.cluster[at], glm::vec2(static_cast<float>(level.n_total(h)), density[point]));
                        ASSERT_EQ(v.select_key[at], glm::vec2(static_cast<float>(c), static_cast<float>(k)));
                    }
    }
    const StrandLineVertices& lines = vertices.strands;
    ASSERT_EQ(lines.position.size(), asset.strand_count() * nc);
    for (size_t c = 0; c < asset.cluster_count(); ++c) {
        const auto [first, end] = asset.cluster_strands(c);
        for (auto i = static_cast<size_t>(first); i < static_cast<size_t>(end); ++i) {
            const glm::vec3* points = rest.strands.points.data() + static_cast<size_t>(asset.strand_order[i]) * nc;
            for (size_t k = 0; k < nc; ++k) {
                ASSERT_EQ(lines.position[i * nc + k], points[k]);
                ASSERT_NEAR(glm::length(lines.tangent[i * nc + k]), 1.0f, 1e-5f);
                ASSERT_EQ(lines.select_key[i * nc + k], glm::vec2(static_cast<float>(c), static_cast<float>(k)));
            }
        }
    }
    EXPECT_EQ(vertices.rest_strands.points, rest.strands.points);
    EXPECT_EQ(vertices.rest_strands.radius, rest.strands.radius);
}

}  // namespace
}  // namespace hairlod
