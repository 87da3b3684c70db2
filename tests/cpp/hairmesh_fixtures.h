#pragma once
// Small hair meshes shared by the hairmesh tests.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "hairlod/hairmesh/hair_mesh.h"

namespace hairlod::test {

// A patch of nx x ny quads (or 2 triangles per quad) on the plane z = 0 over [0, nx] x [0, ny],
// extruded into `layers` - 1 layers that rise along z and lean along x by `lean` per layer.
inline HairMesh grid_hair_mesh(int nx, int ny, int layers, bool triangles = false, float lean = 0.3f) {
    const int columns = nx + 1;
    const auto vertex = [columns](int x, int y) { return y * columns + x; };
    std::vector<glm::vec3> positions;
    for (int layer = 0; layer < layers; ++layer)
        for (int y = 0; y <= ny; ++y)
            for (int x = 0; x <= nx; ++x)
                positions.emplace_back(x + lean * layer * layer * 0.5f, y, 1.0f * layer);
    std::vector<int32_t> sizes, indices;
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
            const int a = vertex(x, y), b = vertex(x + 1, y), c = vertex(x + 1, y + 1), d = vertex(x, y + 1);
            if (triangles) {
                sizes.insert(sizes.end(), {3, 3});
                indices.insert(indices.end(), {a, b, c, a, c, d});
            } else {
                sizes.push_back(4);
                indices.insert(indices.end(), {a, b, c, d});
            }
        }
    return make_hair_mesh(std::move(positions), static_cast<size_t>(columns * (ny + 1)), sizes, indices);
}

// Mean distance from each point to its nearest other point (brute force).
inline double mean_nearest_neighbour(const std::vector<glm::vec2>& points) {
    double sum = 0.0;
    for (size_t i = 0; i < points.size(); ++i) {
        float nearest = std::numeric_limits<float>::max();
        for (size_t j = 0; j < points.size(); ++j)
            if (j != i) nearest = std::min(nearest, glm::distance(points[i], points[j]));
        sum += nearest;
    }
    return sum / static_cast<double>(points.size());
}

}  // namespace hairlod::test
