#pragma once
// Vertex LoD of the curves a view draws: the control points a renderer may leave out because the
// curve through the others stays within a fraction of a pixel of them. Far away a strand or thick
// hair spans a few pixels with all of its control points, and most of them only cost segments
// (vertex level of detail as in hair-meshes-realtime.txt Sec. 3.6.2, which halves a strand's
// vertices in power-of-2 steps; here each curve keeps the points its on-screen error needs).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "hairlod/lod/selection.h"

namespace hairlod {

// The largest distance, in pixels at each point's depth, by which a left-out control point may lie
// from the curve through the kept ones. Every tool's default (CLI, Python API) is this one, read
// through hairlod._core. 0 keeps every point.
inline constexpr float kDefaultVertexTolerancePx = 0.1f;

// Per curve (points [offsets[i], offsets[i + 1]) of `points`), which control points to keep (1) or
// leave out (0). Greedy from the first point: each kept point is followed by the farthest point
// such that every point in between lies within tolerance_px pixels of the chord between them. The
// distance is taken in 3D, so that the shape seen from other directions (shadow and bounce rays)
// holds as well as the camera's, and a pixel is the size of one at the left-out point's depth
// (ScreenWidthBound). A curve's `extent_size` per-point extents (radii, a thick hair's axes; world
// units) add their distance from their linear interpolation along the chord. The first and last
// point of every curve are kept; so is every point behind the camera.
// offsets: curve_count + 1 entries, increasing from 0 to the point count; tolerance_px >= 0 and finite.
std::vector<uint8_t> vertex_lod_keep(std::span<const float> points, std::span<const int64_t> offsets,
                                     std::span<const float> extents, int extent_size, const Camera& camera,
                                     float tolerance_px);

// The viewport preview's vertex LoD (hair-meshes-realtime.txt Sec. 3.6.2: power-of-2 steps, static
// index buffers per step). Curves of `control_points` points each (items, points [items * n_c * 3])
// fall into groups: group g holds items [item_first[g], item_first[g + 1]). Drawn at stride s, an
// item is the chords between its control points 0, s, 2s, ... and its last. Returns [groups *
// strides.size()]: per group and stride, the largest distance (world units, 3D) of a control point
// from the chord drawn in its place; 0 for stride 1 and for an empty group, infinity where a point
// is not finite. strides: each >= 1.
std::vector<float> stride_chord_deviation(std::span<const float> points, int control_points,
                                          std::span<const int64_t> item_first, std::span<const int> strides);

// Per block of groups [block_first[b], block_first[b + 1]): the index (into the strides the
// deviation [groups * stride_count] was measured for, stride 1 first) of the last stride whose
// deviation stays within tolerance_px pixels in every group of the block, a pixel the size of one at
// the nearest depth of the group's bounding sphere (`bounds`: centre, radius; ScreenWidthBound::
// at_nearest). 0 (every point) where a sphere reaches the eye or tolerance_px is 0.
std::vector<int32_t> view_block_strides(std::span<const float> deviation, size_t stride_count,
                                        std::span<const glm::vec4> bounds, std::span<const int64_t> block_first,
                                        const Camera& camera, float tolerance_px);

}  // namespace hairlod
