#include "hairlod/io/tfx.h"

#include <cstdint>
#include <string>
#include <vector>

#include "hairlod/core/error.h"
#include "hairlod/io/byte_reader.h"

namespace hairlod::io {

namespace {

constexpr uint64_t position_bytes = 4 * sizeof(float);

}  // namespace

StrandSet read_tfx(std::span<const std::byte> bytes, const ReadOptions& options) {
    if (bytes.size() < tfx_header_bytes)
        throw Error("file has " + std::to_string(bytes.size()) + " bytes, less than the " +
                    std::to_string(tfx_header_bytes) + "-byte .tfx header");
    ByteReader reader(bytes);
    reader.read<float>("version");
    const uint64_t strand_count = reader.read<uint32_t>("strand count");
    const uint64_t vertices_per_strand = reader.read<uint32_t>("vertices per strand");
    const uint64_t position_offset = reader.read<uint32_t>("vertex position offset");
    const char* optional_arrays[] = {"strand UV", "vertex UV", "strand thickness", "vertex colour"};
    for (const char* name : optional_arrays) {
        // Absent arrays have offset 0; present ones must start after the header, inside the file.
        const uint32_t offset = reader.read<uint32_t>(name);
        if (offset != 0 && (offset < tfx_header_bytes || offset >= bytes.size()))
            throw Error(std::string(name) + " offset " + std::to_string(offset) +
                        " is outside the data (" + std::to_string(tfx_header_bytes) + " to " +
                        std::to_string(bytes.size()) + " bytes)");
    }

    if (strand_count > 0 && vertices_per_strand < 2)
        throw Error("header claims " + std::to_string(vertices_per_strand) +
                    " vertices per strand; every strand needs at least 2");
    if (position_offset < tfx_header_bytes)
        throw Error("vertex position offset " + std::to_string(position_offset) +
                    " points into the " + std::to_string(tfx_header_bytes) + "-byte header");
    const uint64_t vertex_count = strand_count * vertices_per_strand;  // < 2^64
    if (position_offset > bytes.size() ||
        vertex_count > (bytes.size() - position_offset) / position_bytes)
        throw Error("header claims " + std::to_string(strand_count) + " strands of " +
                    std::to_string(vertices_per_strand) + " vertices at byte " +
                    std::to_string(position_offset) + " but the file has only " +
                    std::to_string(bytes.size()) + " bytes");

    reader.seek(position_offset, "vertex positions");
    std::vector<glm::vec3> points(vertex_count);
    for (glm::vec3& p : points) {
        for (int k = 0; k < 3; ++k) p[k] = reader.read<float>("vertex position");
        reader.skip(sizeof(float), "vertex inverse mass");
    }
    const float radius = resolve_default_radius(options, points);
    std::vector<float> radii(points.size(), radius);
    const std::vector<int64_t> counts(strand_count, static_cast<int64_t>(vertices_per_strand));
    return strands_from_counts(std::move(points), counts, std::move(radii));
}

}  // namespace hairlod::io
