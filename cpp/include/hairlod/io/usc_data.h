#pragma once
// USC-HairSalon .data files: the strand list layout (strand_list.h) with x, y, z per point.
#include <cstddef>
#include <span>
#include <vector>

#include "hairlod/core/strand_set.h"
#include "hairlod/io/read_options.h"
#include "hairlod/io/strand_list.h"

namespace hairlod::io {

// Strands with 0 or 1 points are skipped and counted in StrandListFile::skipped_strands.
// The format stores no thickness: radius comes from options (read_options.h).
StrandListFile read_usc_data(std::span<const std::byte> bytes, const ReadOptions& options = {});

// Writes points and curve sizes only (radius and attributes have no place in .data);
// validates `strands` and throws Error if a count does not fit in int32.
std::vector<std::byte> write_usc_data(const StrandSet& strands);

}  // namespace hairlod::io
