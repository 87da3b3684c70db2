#pragma once
// Hair files by path: the format comes from the extension (case-insensitive), errors are
// prefixed with the path, and writes never leave a partial file behind.
//
//   .hair  Cem Yuksel's cyHair            read, write  (cyhair.h)
//   .data  USC-HairSalon                  read, write  (usc_data.h)
//   .bin   CT2Hair                        read         (ct2hair_bin.h)
//   .ply   PLY hair (hairutil / hapPLY)   read         (ply_hair.h)
//   .tfx   AMD TressFX 3/4                read         (tfx.h)
#include <cstddef>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "hairlod/core/strand_set.h"
#include "hairlod/io/read_options.h"

namespace hairlod::io {

enum class HairFormat { CyHair, UscData, Ct2HairBin, Ply, TressFx };

struct HairFormatInfo {
    HairFormat format;
    std::string_view extension;  // with the dot, lower case
    std::string_view description;
    bool writable;
};

// Every format hairlod reads, in the order of the table above.
std::span<const HairFormatInfo> hair_formats();

// Throws Error naming the supported extensions if the path has none of them.
HairFormat hair_format_from_path(const std::filesystem::path& path);

struct HairFileContents {
    StrandSet strands;
    // Strands with fewer than 2 points that the format allows and hairlod drops (.data, .bin).
    size_t skipped_strands = 0;
};

// Parses a file already in memory. Radius for formats without thickness: see ReadOptions.
HairFileContents read_hair_bytes(HairFormat format, std::span<const std::byte> bytes,
                                 const ReadOptions& options = {});

// Serializes to a writable format; throws Error for read-only formats.
std::vector<std::byte> write_hair_bytes(HairFormat format, const StrandSet& strands);

// Reads and parses a file; every Error message starts with "<path>: ".
HairFileContents read_hair_file(const std::filesystem::path& path, const ReadOptions& options = {});

// Writes .hair or .data to a temporary file in the same directory, then renames it over `path`;
// on failure the temporary file is removed and `path` is untouched. Errors start with "<path>: ".
void write_hair_file(const std::filesystem::path& path, const StrandSet& strands);

}  // namespace hairlod::io
