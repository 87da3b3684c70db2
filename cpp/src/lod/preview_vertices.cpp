#include "hairlod/lod/preview_vertices.h"

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace hairlod {

namespace {

// The smallest tangent length taken as a direction; shorter stretches get the fixed (0, 0, 1).
constexpr float kMinTangentLength = 1e-30f;

void resize_thick(ThickStripVertices& v, size_t vertices) {
    v.position.resize(vertices);
    v.tangent.resize(vertices);
    v.major.resize(vertices);
    v.minor.resize(vertices);
    v.cluster.resize(vertices);
    v.select_key.resize(vertices);
}

ThickStripVertices thick_strip_vertices(const LodAsset& asset, size_t level_index, const ThickHairGeometry& g) {
    const ThickHairLevel& level = asset.thick_levels[level_index];
    const auto nc = static_cast<size_t>(asset.control_points);
    const std::vector<float> density = asset.density(level_index);
    ThickStripVertices v;
    resize_thick(v, 2 * level.hair_count() * nc);
    tbb::parallel_for(size_t{0}, asset.cluster_count(), [&](size_t c) {
        for (auto h = static_cast<size_t>(level.cluster_first[c]); h < static_cast<size_t>(level.cluster_first[c + 1]); ++h) {
            const auto n_total = static_cast<float>(level.n_total(h));
            for (size_t k = 0; k < nc; ++k) {
                const size_t point = h * nc + k;
                const glm::vec2 cluster(n_total, density[point]);
                const glm::vec2 key(static_cast<float>(c), static_cast<float>(k));
                for (size_t side = 0; side < 2; ++side) {
                    const size_t at = 2 * point + side;
                    v.position[at] = g.centre[point];
                    v.tangent[at] = g.tangent[point];
                    v.major[at] = g.major[point];
                    v.minor[at] = g.minor[point];
                    v.cluster[at] = cluster;
                    v.select_key[at] = key;
                }
            }
        }
    });
    return v;
}

StrandLineVertices strand_line_vertices(const LodAsset& asset, const StrandSet& rest) {
    const auto nc = static_cast<size_t>(asset.control_points);
    StrandLineVertices v;
    const size_t vertices = asset.strand_count() * nc;
    v.position.resize(vertices);
    v.tangent.resize(vertices);
    v.select_key.resize(vertices);
    tbb::parallel_for(size_t{0}, asset.cluster_count(), [&](size_t c) {
        const auto [first, end] = asset.cluster_strands(c);
        for (auto i = static_cast<size_t>(first); i < static_cast<size_t>(end); ++i) {
            const glm::vec3* points = rest.points.data() + static_cast<size_t>(asset.strand_order[i]) * nc;
            for (size_t k = 0; k < nc; ++k) {
                v.position[i * nc + k] = points[k];
                v.tangent[i * nc + k] = polyline_tangent(points, nc, k);
                v.select_key[i * nc + k] = glm::vec2(static_cast<float>(c), static_cast<float>(k));
            }
        }
    });
    return v;
}

}  // namespace

glm::vec3 polyline_tangent(const glm::vec3* points, size_t count, size_t k) {
    const glm::vec3 step = points[k + 1 < count ? k + 1 : k] - points[k > 0 ? k - 1 : k];
    const float length = glm::length(step);
    return length > kMinTangentLength ? step / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

PreviewVertices preview_vertices(const LodAsset& asset) {
    LodGeometry rest = asset.rest_geometry();
    PreviewVertices vertices;
    for (size_t l = 0; l < asset.thick_levels.size(); ++l)
        vertices.levels.push_back(thick_strip_vertices(asset, l, rest.levels[l]));
    vertices.strands = strand_line_vertices(asset, rest.strands);
    vertices.rest_strands = std::move(rest.strands);
    return vertices;
}

}  // namespace hairlod
