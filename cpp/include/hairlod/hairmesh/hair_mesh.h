#pragma once
// HairMesh: a scalp polygon mesh (the root layer) extruded into layers that share its topology
// (hair-meshes-realtime.txt Sec. 2.2). Each root face and its extrusions form a bundle.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace hairlod {

// A face as the four corners of a bilinear patch (hair-meshes-realtime.txt Sec. 3.1): a quad in
// polygon order, or a triangle with its last vertex duplicated.
struct FaceCorners {
    std::array<int32_t, 4> vertex;  // root-layer vertex indices
    std::array<int32_t, 4> corner;  // indices into HairMesh::corner_uv
    bool triangle;
};

// Bilinear weights of corners 0..3 at (s, t) in [0, 1]^2: corner 0 at (0, 0), 1 at (1, 0),
// 2 at (1, 1), 3 at (0, 1).
inline std::array<float, 4> bilinear_weights(float s, float t) {
    return {(1.0f - s) * (1.0f - t), s * (1.0f - t), s * t, (1.0f - s) * t};
}

struct HairMesh {
    size_t vertex_count = 0;            // vertices per layer, V
    std::vector<glm::vec3> positions;   // layer-major: layer l, vertex i at l * V + i
    std::vector<int32_t> face_offsets{0};  // face f owns corners [face_offsets[f], face_offsets[f + 1])
    std::vector<int32_t> corner_vertices;  // root-layer vertex of each corner; 3 or 4 per face
    std::vector<glm::vec2> corner_uv;      // styling uv of each corner (seams allowed), or empty
    std::vector<float> w;                  // styling w of each position, or empty (path length)

    size_t layer_count() const { return vertex_count ? positions.size() / vertex_count : 0; }
    size_t face_count() const { return face_offsets.size() - 1; }
    size_t corner_count() const { return corner_vertices.size(); }
    size_t face_size(size_t face) const {
        return static_cast<size_t>(face_offsets[face + 1] - face_offsets[face]);
    }
    const glm::vec3& position(size_t layer, size_t vertex) const {
        return positions[layer * vertex_count + vertex];
    }
    FaceCorners face_corners(size_t face) const;
    // Area of the face on the root layer (the two triangles of a quad's diagonals averaged).
    double root_face_area(size_t face) const;
    // Throws Error naming the first problem: sizes, index ranges, repeated vertices, NaN/Inf.
    void validate() const;
};

// Builds a validated HairMesh from layer-major positions (layer_count * vertex_count) and polygons
// given by their sizes and vertex lists. Polygons with more than 4 vertices are split into a fan of
// quads (and a final triangle when the count is odd), their corner uv split alike.
HairMesh make_hair_mesh(std::vector<glm::vec3> positions, size_t vertex_count,
                        std::span<const int32_t> polygon_sizes,
                        std::span<const int32_t> polygon_vertices,
                        std::span<const glm::vec2> polygon_uv = {}, std::vector<float> w = {});

}  // namespace hairlod
