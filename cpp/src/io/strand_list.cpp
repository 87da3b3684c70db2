#include "hairlod/io/strand_list.h"

#include <cstdint>
#include <string>
#include <vector>

#include "hairlod/core/error.h"
#include "hairlod/io/byte_reader.h"

namespace hairlod::io {

namespace {

constexpr size_t count_bytes = sizeof(int32_t);

}  // namespace

StrandListFile read_strand_list(std::span<const std::byte> bytes, int floats_per_point,
                                const ReadOptions& options) {
    if (floats_per_point < 3) throw Error("a strand list point needs at least 3 floats");
    const size_t point_bytes = static_cast<size_t>(floats_per_point) * sizeof(float);
    ByteReader reader(bytes);
    const int32_t stored_strand_count = reader.read<int32_t>("strand count");
    if (stored_strand_count < 0)
        throw Error("strand count is negative (" + std::to_string(stored_strand_count) + ")");
    const auto strand_count = static_cast<size_t>(stored_strand_count);
    if (strand_count > reader.remaining() / count_bytes)
        throw Error("header claims " + std::to_string(strand_count) +
                    " strands but the file has only " + std::to_string(bytes.size()) + " bytes");

    // First pass: check every strand against the file size and count the points, so that
    // nothing is allocated for a file whose counts lie.
    const size_t first_strand = reader.position();
    size_t kept_points = 0;
    size_t kept_strands = 0;
    for (size_t s = 0; s < strand_count; ++s) {
        const int32_t stored_n = reader.read<int32_t>("strand point count");
        if (stored_n < 0)
            throw Error("strand " + std::to_string(s) + " has a negative point count (" +
                        std::to_string(stored_n) + ")");
        const auto n = static_cast<size_t>(stored_n);
        if (n > reader.remaining() / point_bytes)
            throw Error("strand " + std::to_string(s) + " claims " + std::to_string(n) +
                        " points but only " + std::to_string(reader.remaining()) +
                        " bytes are left");
        reader.skip(n * point_bytes, "strand points");
        if (n >= 2) {
            kept_points += n;
            ++kept_strands;
        }
    }
    if (reader.remaining() != 0)
        throw Error(std::to_string(reader.remaining()) + " unexpected bytes after the last of " +
                    std::to_string(strand_count) + " strands");

    // Second pass: read the points of the strands that are curves.
    std::vector<glm::vec3> points;
    std::vector<int64_t> counts;
    points.reserve(kept_points);
    counts.reserve(kept_strands);
    reader.seek(first_strand, "strand list");
    const size_t unused_bytes = point_bytes - 3 * sizeof(float);
    for (size_t s = 0; s < strand_count; ++s) {
        const auto n = static_cast<size_t>(reader.read<int32_t>("strand point count"));
        if (n < 2) {
            reader.skip(n * point_bytes, "strand points");
            continue;
        }
        counts.push_back(static_cast<int64_t>(n));
        const size_t first = points.size();
        points.resize(first + n);
        if (unused_bytes == 0) {
            reader.read_array(point_floats(std::span(points).subspan(first, n)), "strand points");
            continue;
        }
        for (size_t i = first; i < first + n; ++i) {
            reader.read_array(point_floats(std::span(points).subspan(i, 1)), "strand points");
            reader.skip(unused_bytes, "point extra values");
        }
    }
    const float radius = resolve_default_radius(options, points);
    std::vector<float> radii(points.size(), radius);
    return {strands_from_counts(std::move(points), counts, std::move(radii)),
            strand_count - kept_strands};
}

}  // namespace hairlod::io
