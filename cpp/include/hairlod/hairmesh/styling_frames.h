#pragma once
// Styling coordinates (hair-meshes-realtime.txt Sec. 3.4): a uvw texture-space embedding of the
// hair mesh and per-vertex object-space directions u, v shared by every bundle that uses the
// vertex, so styling offsets carry no seams between bundles.
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "hairlod/hairmesh/hair_mesh.h"

namespace hairlod {

struct StylingFrames {
    std::vector<glm::vec2> corner_uv;  // the mesh's uv, or default_root_uv when it has none
    std::vector<glm::vec3> u, v;       // unit directions per position (layer-major), Bhokare 2024 Eq. 1
    std::vector<float> w;              // the mesh's w, or path length from the root layer
};

// Planar projection of the root layer onto the plane normal to its area-weighted mean normal,
// in object units; used when the mesh carries no uv (give uv for closed or strongly curved scalps).
std::vector<glm::vec2> default_root_uv(const HairMesh& mesh);

// Bhokare 2024 Eq. 1-3 per layer: u, v of a vertex are the texture-area-weighted means of the linear maps of
// the corner triangles around it (the vertex and its two face edges, Fig. 5), normalised; corner
// triangles that are flat in uv are skipped. Where they cancel or a layer collapses, the vertex
// keeps the directions of the layer below. A root-layer vertex without usable directions (a pole
// that its uv wraps around, uv collapsed to a point) takes the root layer's mean directions, or,
// when those cancel too (a closed cap), a frame from object space: u a world axis made tangent to
// the vertex normal n, v = n x u. A root layer of zero object-space area is an Error.
StylingFrames compute_styling_frames(const HairMesh& mesh);

}  // namespace hairlod
