#include "hairlod/io/ct2hair_bin.h"

namespace hairlod::io {

StrandListFile read_ct2hair_bin(std::span<const std::byte> bytes, const ReadOptions& options) {
    return read_strand_list(bytes, ct2hair_floats_per_point, options);
}

}  // namespace hairlod::io
