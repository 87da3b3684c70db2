#pragma once
// Shared by the fuzz targets: the input as bytes, and a check that crashes (so libFuzzer keeps
// the input) when a written-then-read StrandSet differs from the one written.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <vector>

#include "hairlod/core/strand_set.h"

namespace hairlod::fuzz {

inline std::span<const std::byte> input_bytes(const uint8_t* data, size_t size) {
    return std::as_bytes(std::span(data, size));
}

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

inline void require_same_strands(const StrandSet& written, const StrandSet& read_back,
                                 bool compare_radius) {
    bool same = written.offsets == read_back.offsets && same_bits(written.points, read_back.points) &&
                (!compare_radius || same_bits(written.radius, read_back.radius)) &&
                written.attributes.size() == read_back.attributes.size();
    for (const auto& [name, attribute] : written.attributes) {
        const Attribute* other = read_back.find_attribute(name);
        same = same && other && other->domain == attribute.domain &&
               other->components == attribute.components && same_bits(other->values, attribute.values);
    }
    if (!same) std::abort();
}

}  // namespace hairlod::fuzz
