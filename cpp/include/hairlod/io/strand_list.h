#pragma once
// The length-prefixed strand list layout shared by USC-HairSalon .data and CT2Hair .bin files:
// int32 strand count, then per strand an int32 point count n and n points of
// `floats_per_point` little-endian float32 values, of which the first three are x, y, z.
#include <cstddef>
#include <span>

#include "hairlod/core/strand_set.h"
#include "hairlod/io/read_options.h"

namespace hairlod::io {

struct StrandListFile {
    StrandSet strands;
    // Strands stored with 0 or 1 points (empty scalp roots in USC-HairSalon files) are not curves;
    // they are dropped and counted here.
    size_t skipped_strands = 0;
};

// Throws Error on truncated or inconsistent data, negative counts, trailing bytes, or non-finite points.
StrandListFile read_strand_list(std::span<const std::byte> bytes, int floats_per_point,
                                const ReadOptions& options);

}  // namespace hairlod::io
