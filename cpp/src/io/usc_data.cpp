#include "hairlod/io/usc_data.h"

#include <cstdint>
#include <limits>
#include <string>

#include "hairlod/core/error.h"
#include "hairlod/io/byte_writer.h"

namespace hairlod::io {

StrandListFile read_usc_data(std::span<const std::byte> bytes, const ReadOptions& options) {
    return read_strand_list(bytes, 3, options);
}

std::vector<std::byte> write_usc_data(const StrandSet& strands) {
    strands.validate();
    constexpr size_t int32_max = std::numeric_limits<int32_t>::max();
    if (strands.curve_count() > int32_max)
        throw Error(".data stores at most " + std::to_string(int32_max) + " strands, got " +
                    std::to_string(strands.curve_count()));
    ByteWriter writer;
    writer.reserve(sizeof(int32_t) * (1 + strands.curve_count()) +
                   3 * sizeof(float) * strands.point_count());
    writer.write(static_cast<int32_t>(strands.curve_count()));
    for (size_t c = 0; c < strands.curve_count(); ++c) {
        const std::span<const glm::vec3> curve = strands.curve_points(c);
        if (curve.size() > int32_max)
            throw Error("curve " + std::to_string(c) + " has " + std::to_string(curve.size()) +
                        " points; .data stores at most " + std::to_string(int32_max));
        writer.write(static_cast<int32_t>(curve.size()));
        writer.write_array(point_floats(curve));
    }
    return std::move(writer).take();
}

}  // namespace hairlod::io
