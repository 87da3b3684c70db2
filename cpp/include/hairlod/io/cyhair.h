#pragma once
// Cem Yuksel's .hair (cyHair) files: a 128-byte little-endian header ("HAIR", hair count,
// point count, array flags, defaults, 88-byte info text), then the arrays the flags name:
// segments (uint16 per hair), points (float3), thickness (float), transparency (float),
// colour (float3), each per point.
//
// Mapping to StrandSet: thickness is the strand diameter, so radius = thickness / 2 (the
// header's default thickness when the array is absent); the transparency and colour arrays
// become point attributes "transparency" (1 component) and "color" (3 components) only when
// the file has them. Header defaults and the info text are kept in CyHairHeader.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "hairlod/core/strand_set.h"

namespace hairlod::io {

inline constexpr size_t cyhair_header_bytes = 128;
inline constexpr size_t cyhair_info_bytes = 88;

// The header fields that the arrays do not already carry.
struct CyHairHeader {
    float default_thickness = 1.0f;
    float default_transparency = 0.0f;
    glm::vec3 default_color{1.0f};
    std::string info;  // at most cyhair_info_bytes, no NUL characters
};

struct CyHairFile {
    StrandSet strands;
    CyHairHeader header;
};

// Throws Error on a bad signature, missing points array, truncated or oversized data, counts that
// disagree, hairs with 0 segments, or non-finite values.
CyHairFile read_cyhair(std::span<const std::byte> bytes);

// Always writes points and thickness (2 * radius); writes the segments array unless every curve
// has the same size (the header's default segment count then says it); writes transparency and
// colour arrays when `strands` has the "transparency" (point, 1) and "color" (point, 3)
// attributes. Other attributes have no place in the format and are not written.
// read_cyhair(write_cyhair(s, h)) reproduces s and h exactly.
std::vector<std::byte> write_cyhair(const StrandSet& strands, const CyHairHeader& header = {});

}  // namespace hairlod::io
