#pragma once
// AMD TressFX 3/4 .tfx files, read only: a little-endian header {float version; uint32 strand
// count; uint32 vertices per strand; uint32 offsets of the vertex positions, strand UVs, vertex
// UVs, strand thickness and vertex colours; uint32 reserved[32]}, then at the position offset
// strand count * vertices per strand float4 positions (x, y, z and an inverse mass hairlod does
// not use). Only positions are read; radius comes from the read options.
#include <cstddef>
#include <span>

#include "hairlod/core/strand_set.h"
#include "hairlod/io/read_options.h"

namespace hairlod::io {

inline constexpr size_t tfx_header_bytes = 160;

// Throws Error on a truncated header, offsets outside the file, fewer than 2 vertices per strand,
// counts the file is too small for, or non-finite positions.
StrandSet read_tfx(std::span<const std::byte> bytes, const ReadOptions& options = {});

}  // namespace hairlod::io
