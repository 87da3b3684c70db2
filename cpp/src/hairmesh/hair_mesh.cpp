#include "hairlod/hairmesh/hair_mesh.h"

#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod {

namespace {

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
bool finite(const glm::vec2& p) { return std::isfinite(p.x) && std::isfinite(p.y); }

}  // namespace

FaceCorners HairMesh::face_corners(size_t face) const {
    const int32_t first = face_offsets[face];
    const bool triangle = face_size(face) == 3;
    FaceCorners corners{};
    corners.triangle = triangle;
    for (int k = 0; k < 4; ++k) {
        const int32_t corner = first + (triangle && k == 3 ? 2 : k);
        corners.corner[k] = corner;
        corners.vertex[k] = corner_vertices[corner];
    }
    return corners;
}

double HairMesh::root_face_area(size_t face) const {
    const FaceCorners c = face_corners(face);
    const glm::dvec3 p0(position(0, c.vertex[0])), p1(position(0, c.vertex[1])),
        p2(position(0, c.vertex[2])), p3(position(0, c.vertex[3]));
    // Half the cross product of the diagonals: exact for planar quads and for triangles (p3 = p2).
    return 0.5 * glm::length(glm::cross(p2 - p0, p3 - p1));
}

void HairMesh::validate() const {
    if (vertex_count < 3) throw Error("hair mesh needs at least 3 vertices per layer, got " + std::to_string(vertex_count));
    if (positions.size() % vertex_count != 0)
        throw Error("hair mesh has " + std::to_string(positions.size()) + " positions, not a multiple of " +
                    std::to_string(vertex_count) + " vertices per layer");
    if (layer_count() < 2)
        throw Error("hair mesh needs the root layer and at least one extrusion layer, got " +
                    std::to_string(layer_count()) + " layer");
    for (size_t i = 0; i < positions.size(); ++i)
        if (!finite(positions[i]))
            throw Error("hair mesh position of layer " + std::to_string(i / vertex_count) + " vertex " +
                        std::to_string(i % vertex_count) + " is not finite (NaN or Inf)");
    if (face_offsets.empty() || face_offsets.front() != 0) throw Error("hair mesh face offsets must start with 0");
    if (face_count() == 0) throw Error("hair mesh has no faces");
    if (static_cast<size_t>(face_offsets.back()) != corner_vertices.size())
        throw Error("hair mesh face offsets end at " + std::to_string(face_offsets.back()) + " but there are " +
                    std::to_string(corner_vertices.size()) + " corners");
    for (size_t f = 0; f < face_count(); ++f) {
        const int32_t size = face_offsets[f + 1] - face_offsets[f];
        if (size != 3 && size != 4)
            throw Error("hair mesh face " + std::to_string(f) + " has " + std::to_string(size) +
                        " vertices; faces are triangles or quads");
        for (int32_t a = face_offsets[f]; a < face_offsets[f + 1]; ++a) {
            const int32_t vertex = corner_vertices[a];
            if (vertex < 0 || static_cast<size_t>(vertex) >= vertex_count)
                throw Error("hair mesh face " + std::to_string(f) + " uses vertex " + std::to_string(vertex) +
                            ", outside [0, " + std::to_string(vertex_count) + ")");
            for (int32_t b = face_offsets[f]; b < a; ++b)
                if (corner_vertices[b] == vertex)
                    throw Error("hair mesh face " + std::to_string(f) + " is degenerate: vertex " +
                                std::to_string(vertex) + " appears twice");
        }
    }
    if (!corner_uv.empty() && corner_uv.size() != corner_vertices.size())
        throw Error("hair mesh uv has " + std::to_string(corner_uv.size()) + " values for " +
                    std::to_string(corner_vertices.size()) + " face corners");
    for (size_t i = 0; i < corner_uv.size(); ++i)
        if (!finite(corner_uv[i])) throw Error("hair mesh uv of corner " + std::to_string(i) + " is not finite");
    if (!w.empty() && w.size() != positions.size())
        throw Error("hair mesh w has " + std::to_string(w.size()) + " values for " +
                    std::to_string(positions.size()) + " positions");
    for (size_t i = 0; i < w.size(); ++i)
        if (!std::isfinite(w[i])) throw Error("hair mesh w of position " + std::to_string(i) + " is not finite");
}

HairMesh make_hair_mesh(std::vector<glm::vec3> positions, size_t vertex_count,
                        std::span<const int32_t> polygon_sizes, std::span<const int32_t> polygon_vertices,
                        std::span<const glm::vec2> polygon_uv, std::vector<float> w) {
    HairMesh mesh;
    mesh.vertex_count = vertex_count;
    mesh.positions = std::move(positions);
    mesh.w = std::move(w);
    const bool has_uv = !polygon_uv.empty();
    if (has_uv && polygon_uv.size() != polygon_vertices.size())
        throw Error("hair mesh uv has " + std::to_string(polygon_uv.size()) + " values for " +
                    std::to_string(polygon_vertices.size()) + " polygon corners");
    size_t first = 0;
    const auto add_face = [&](std::initializer_list<size_t> corners) {
        for (size_t corner : corners) {
            mesh.corner_vertices.push_back(polygon_vertices[first + corner]);
            if (has_uv) mesh.corner_uv.push_back(polygon_uv[first + corner]);
        }
        mesh.face_offsets.push_back(static_cast<int32_t>(mesh.corner_vertices.size()));
    };
    for (size_t p = 0; p < polygon_sizes.size(); ++p) {
        const int32_t size = polygon_sizes[p];
        if (size < 3) throw Error("hair mesh polygon " + std::to_string(p) + " has " + std::to_string(size) + " vertices; at least 3 are needed");
        if (first + static_cast<size_t>(size) > polygon_vertices.size())
            throw Error("hair mesh polygon sizes need more vertex indices than the " +
                        std::to_string(polygon_vertices.size()) + " given");
        // Fan of quads (0, k, k+1, k+2) from corner 0, then a triangle if one corner is left.
        const auto n = static_cast<size_t>(size);
        size_t k = 1;
        for (; k + 2 < n; k += 2) add_face({0, k, k + 1, k + 2});
        if (k + 1 < n) add_face({0, k, k + 1});
        first += n;
    }
    if (first != polygon_vertices.size())
        throw Error("hair mesh polygon sizes account for " + std::to_string(first) + " of the " +
                    std::to_string(polygon_vertices.size()) + " vertex indices");
    mesh.validate();
    return mesh;
}

}  // namespace hairlod
