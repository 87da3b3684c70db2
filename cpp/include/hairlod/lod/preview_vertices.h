#pragma once
// Vertex arrays of a viewport preview of an LoD asset at its rest pose (a shader skins them per frame
// with FrameSkinning's maps): camera-facing strips for thick hairs, lines for strands, in the layout
// ViewSelection::indices addresses (item-major, n_c control points per item; two strip vertices per
// control point; strands in hierarchy order). Each vertex carries its L0 cluster and control point,
// which the shader looks the frame's selected level up with. Built once per asset in one parallel
// pass (234 ms against 287 ms for the former numpy passes on 100k strands in a plain process; inside
// Blender the first touch of the ~70 MB they fill dominates either way).
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "hairlod/core/strand_set.h"
#include "hairlod/lod/lod_asset.h"

namespace hairlod {

// One thick level: two identical vertices per control point (the strip's sides are made in the
// shader from the semi-axes). What the viewport shader needs to shade the aggregated BCSDF
// (hair-lod-aggregated-bcsdf.txt Sec. 4): centre, the centre curve's tangent, the major and minor
// semi-axis vectors, and the hair's strand count n_total with its density rho at the point.
struct ThickStripVertices {
    std::vector<glm::vec3> position, tangent, major, minor;
    std::vector<glm::vec2> cluster;     // (n_total, rho)
    std::vector<glm::vec2> select_key;  // (L0 cluster, control point), as floats
};

// The strands: one vertex per control point, strands in hierarchy order (LodAsset::strand_order).
struct StrandLineVertices {
    std::vector<glm::vec3> position;
    std::vector<glm::vec3> tangent;  // unit: central differences, one-sided at the ends; (0, 0, 1) where
                                     // the stretch has no length
    std::vector<glm::vec2> select_key;
};

struct PreviewVertices {
    std::vector<ThickStripVertices> levels;  // L0 first
    StrandLineVertices strands;
    StrandSet rest_strands;                  // the decoded strands at n_c points, input order
};

// Unit tangent of a polyline at point k of `count` points (central differences, one-sided at the
// ends; (0, 0, 1) for a stretch without length).
glm::vec3 polyline_tangent(const glm::vec3* points, size_t count, size_t k);

PreviewVertices preview_vertices(const LodAsset& asset);

}  // namespace hairlod
