#pragma once
// PLY hair files as written by hairutil (hapPLY): ascii, binary_little_endian or
// binary_big_endian; any scalar or list properties of any PLY type.
//
// Required: element "vertex" with scalar x, y, z, and element "strand" with a per-strand point
// count property: "nsegs" (segments, so nsegs + 1 points), "nverts" or "vertex_count" (points).
// Strand points sum to the vertex count; strand i owns the next points in vertex order.
// Optional vertex properties: red, green, blue (all three; uchar scaled to [0, 1], float or
// double as stored) become the point attribute "color" (3 components); "radius" is the radius,
// "thickness" or "width" the diameter (radius = value / 2). Without them, radius comes from the
// read options. Other elements (e.g. "edge") and properties are parsed and ignored.
#include <cstddef>
#include <span>

#include "hairlod/core/strand_set.h"
#include "hairlod/io/read_options.h"

namespace hairlod::io {

// Throws Error on a malformed header, truncated or trailing data, counts that disagree,
// strands with fewer than 2 points, or non-finite values.
StrandSet read_ply_hair(std::span<const std::byte> bytes, const ReadOptions& options = {});

}  // namespace hairlod::io
