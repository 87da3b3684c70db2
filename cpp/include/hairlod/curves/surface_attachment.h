#pragma once
// Curves attached to a triangle mesh, moved with it as Blender's "Deform Curves on Surface" node
// moves hair on an animated head: every curve has a UV coordinate on the mesh (Blender's
// surface_uv_coordinate), which finds its root triangle and barycentric weights in the mesh's UV
// map, and the whole curve turns and moves rigidly with the frame of that root point:
//   normal n = normalize(sum_i w_i N_i) over the triangle's corner normals,
//   x = normalize(n x (P_1 - P_0)) (the edge from the triangle's first vertex to its second),
//   y = normalize(n x x),  origin o = sum_i w_i P_i.
// A curve moves from one pose of the mesh to another by p' = R' R^T (p - o) + o' (R = [x y n]).
// Smooth skinning from guides cannot reproduce this where the mesh shears (neighbouring triangles
// turn differently, and the edge that fixes x changes from one triangle to the next), so the LoD
// preview moves its strands by these transforms when the hair is attached this way.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace hairlod {

// A triangle mesh in Blender's layout: a position per vertex, the vertex of every face corner, the
// three corners of every triangle (loop triangles) and a normal per corner (Blender's corner normals:
// smooth, flat, auto-smooth or custom alike).
struct SurfaceMesh {
    std::span<const glm::vec3> positions;
    std::span<const int32_t> corner_verts;
    std::span<const glm::ivec3> triangles;
    std::span<const glm::vec3> corner_normals;
};

// Where each curve's root lies: the index of its triangle, or -1 when its UV coordinate lies in no
// triangle of the UV map or inside more than one (Blender leaves such curves where they are), and the
// barycentric weights of the root in it.
struct SurfaceBinding {
    std::vector<int32_t> triangle;
    std::vector<glm::vec3> weights;
};

// The triangle of every UV coordinate in a UV map of `corner_uvs` (one per face corner): the triangle
// it lies in, or one it lies on the edge of (within 1e-5 in barycentric weight, the weights then
// clamped to [0, 1]); -1 where it lies in none, or well inside two (an overlapping UV map). A uniform
// grid over the triangles' UV bounds finds the candidates. Throws Error when a triangle names a
// corner out of range.
SurfaceBinding bind_by_uv(std::span<const glm::vec2> root_uvs, std::span<const glm::vec2> corner_uvs,
                          std::span<const glm::ivec3> triangles);

// An affine map p -> linear p + offset.
struct Affine {
    glm::mat3 linear{1.0f};
    glm::vec3 offset{0.0f};
};

// Moves curves with their surface. Made from the pose of the mesh the curves were taken at (the
// rest pose of an LoD asset), it gives for any later pose of the same mesh (its positions and corner
// normals; the topology is the rest pose's) the rigid transform of every curve, in the curves' object
// space: surface_to_curves maps the mesh's object space into the curves' (inverse(curves world
// matrix) x surface world matrix), at the rest pose and at each pose.
class SurfaceFollow {
public:
    // Throws Error when the binding's arrays differ in length, when they name a triangle the mesh lacks,
    // when a triangle or corner of the mesh names one out of range, or when the matrix is not invertible.
    SurfaceFollow(const SurfaceBinding& binding, const SurfaceMesh& rest_mesh, const glm::mat4& rest_surface_to_curves);

    // Per curve, the rows of the 3 x 4 affine map [R | t] taking its points at the rest pose to the
    // pose of the mesh with these positions and corner normals (3 vec4 per curve); the identity for a
    // curve without a triangle, or whose frame is degenerate at the rest pose or in this one (it stays
    // where it was). Throws Error when the counts of positions or normals differ from the rest pose's.
    std::vector<glm::vec4> transforms(std::span<const glm::vec3> positions, std::span<const glm::vec3> corner_normals,
                                      const glm::mat4& surface_to_curves) const;
    // The same rows written into `rows` (3 per curve, every entry written): a caller that keeps one
    // array from pose to pose (the preview, 4.8 MB for 100k curves) writes into memory already mapped,
    // where a new array per pose costs a page fault per 4 kB. Throws Error when `rows` does not hold
    // 3 per curve.
    void transforms(std::span<const glm::vec3> positions, std::span<const glm::vec3> corner_normals,
                    const glm::mat4& surface_to_curves, std::span<glm::vec4> rows) const;

    size_t curve_count() const { return bound_.size(); }
    // Curves that move with the surface (a triangle and a proper frame at the rest pose).
    size_t bound_count() const { return roots_.size(); }
    bool is_bound(size_t curve) const { return bound_.at(curve) != 0; }

private:
    // A bound curve's root, with the mesh's indirections resolved once (a pose's positions and normals
    // are read without chains of dependent loads), in curve order (the transforms are written in order).
    struct Root {
        glm::ivec3 vertices;
        glm::ivec3 corners;
        glm::vec3 weights;
        uint32_t curve;
        Affine rest_inverse;  // inverse of (surface_to_curves x root frame) at the rest pose
    };
    std::vector<Root> roots_;
    std::vector<uint8_t> bound_;
    size_t vertex_count_ = 0, corner_count_ = 0;
};

}  // namespace hairlod
