#pragma once
// CT2Hair .bin files: the strand list layout (strand_list.h) with 7 floats per point, x, y, z
// followed by 4 values hairlod does not use. Read only.
#include <cstddef>
#include <span>

#include "hairlod/io/read_options.h"
#include "hairlod/io/strand_list.h"

namespace hairlod::io {

inline constexpr int ct2hair_floats_per_point = 7;

// Strands with 0 or 1 points are skipped and counted in StrandListFile::skipped_strands.
// The format stores no thickness: radius comes from options (read_options.h).
StrandListFile read_ct2hair_bin(std::span<const std::byte> bytes, const ReadOptions& options = {});

}  // namespace hairlod::io
