#include "hairlod/io/cyhair.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>

#include "hairlod/core/error.h"
#include "hairlod/io/byte_reader.h"
#include "hairlod/io/byte_writer.h"
#include "require_finite.h"

namespace hairlod::io {

namespace {

constexpr std::string_view signature = "HAIR";

// Bits of the header's array flags.
constexpr uint32_t has_segments = 1u << 0;
constexpr uint32_t has_points = 1u << 1;
constexpr uint32_t has_thickness = 1u << 2;
constexpr uint32_t has_transparency = 1u << 3;
constexpr uint32_t has_color = 1u << 4;

constexpr const char* transparency_name = "transparency";
constexpr const char* color_name = "color";

std::vector<float> read_floats(ByteReader& reader, size_t count, std::string_view what) {
    reader.require(count * sizeof(float), what);
    std::vector<float> values(count);
    reader.read_array(std::span(values), what);
    return values;
}

// A point attribute to write, or nullptr; throws if it exists with the wrong shape.
const Attribute* point_attribute(const StrandSet& strands, const char* name, int components) {
    const Attribute* attribute = strands.find_attribute(name);
    if (attribute &&
        (attribute->domain != AttributeDomain::Point || attribute->components != components))
        throw Error("attribute '" + std::string(name) + "' must be a point attribute with " +
                    std::to_string(components) + " component(s) to be written to .hair");
    return attribute;
}

}  // namespace

CyHairFile read_cyhair(std::span<const std::byte> bytes) {
    if (bytes.size() < cyhair_header_bytes)
        throw Error("file has " + std::to_string(bytes.size()) + " bytes, less than the " +
                    std::to_string(cyhair_header_bytes) + "-byte .hair header");
    ByteReader reader(bytes);
    const std::span<const std::byte> magic = reader.read_bytes(signature.size(), "signature");
    if (!std::equal(magic.begin(), magic.end(), signature.begin(),
                    [](std::byte b, char c) { return b == static_cast<std::byte>(c); }))
        throw Error("not a .hair file: it does not start with \"HAIR\"");

    const uint64_t hair_count = reader.read<uint32_t>("hair count");
    const uint64_t point_count = reader.read<uint32_t>("point count");
    const uint32_t flags = reader.read<uint32_t>("flags");
    const uint64_t default_segments = reader.read<uint32_t>("default segments");
    CyHairFile file;
    CyHairHeader& header = file.header;
    header.default_thickness = reader.read<float>("default thickness");
    header.default_transparency = reader.read<float>("default transparency");
    for (int k = 0; k < 3; ++k) header.default_color[k] = reader.read<float>("default colour");
    const std::span<const std::byte> info = reader.read_bytes(cyhair_info_bytes, "info");
    const auto info_end = std::find(info.begin(), info.end(), std::byte{0});
    header.info.assign(reinterpret_cast<const char*>(info.data()),
                       static_cast<size_t>(info_end - info.begin()));

    if (!(flags & has_points)) throw Error("file has no points array (flag bit 1 is not set)");

    // Both counts are below 2^32, so these sizes cannot overflow 64 bits.
    const uint64_t bytes_per_point = 3 * sizeof(float) + (flags & has_thickness ? 4 : 0) +
                                     (flags & has_transparency ? 4 : 0) +
                                     (flags & has_color ? 12 : 0);
    const uint64_t expected_size = cyhair_header_bytes +
                                   (flags & has_segments ? hair_count * sizeof(uint16_t) : 0) +
                                   point_count * bytes_per_point;
    const std::string claim = "header claims " + std::to_string(hair_count) + " strands and " +
                              std::to_string(point_count) + " points (" +
                              std::to_string(expected_size) + " bytes)";
    if (expected_size > bytes.size())
        throw Error(claim + " but the file has only " + std::to_string(bytes.size()) + " bytes");
    if (expected_size < bytes.size())
        throw Error(claim + " but the file has " + std::to_string(bytes.size()) + " bytes");

    std::vector<int64_t> counts;
    if (flags & has_segments) {
        counts.resize(hair_count);
        std::vector<uint16_t> segments_array(hair_count);
        reader.read_array(std::span(segments_array), "segments");
        uint64_t total = 0;
        for (uint64_t h = 0; h < hair_count; ++h) {
            const uint16_t segments = segments_array[h];
            if (segments == 0)
                throw Error("strand " + std::to_string(h) +
                            " has 0 segments; every strand needs at least 1");
            counts[h] = segments + 1;
            total += counts[h];
        }
        if (total != point_count)
            throw Error("segments array adds up to " + std::to_string(total) +
                        " points but the header claims " + std::to_string(point_count));
    } else {
        if (hair_count > 0 && default_segments == 0)
            throw Error("default segment count is 0; every strand needs at least 1");
        if (hair_count * (default_segments + 1) != point_count)
            throw Error(std::to_string(hair_count) + " strands of " +
                        std::to_string(default_segments) + " default segments need " +
                        std::to_string(hair_count * (default_segments + 1)) +
                        " points but the header claims " + std::to_string(point_count));
        counts.assign(hair_count, static_cast<int64_t>(default_segments + 1));
    }

    std::vector<glm::vec3> points(point_count);
    reader.read_array(point_floats(points), "points");

    std::vector<float> radius;
    if (flags & has_thickness) {
        radius = read_floats(reader, point_count, "thickness");
        for (float& r : radius) r *= 0.5f;
    } else {
        if (!std::isfinite(header.default_thickness) || header.default_thickness < 0.0f)
            throw Error("default thickness must be finite and >= 0, got " +
                        std::to_string(header.default_thickness));
        radius.assign(point_count, 0.5f * header.default_thickness);
    }

    std::vector<float> transparency;
    if (flags & has_transparency) {
        transparency = read_floats(reader, point_count, transparency_name);
        require_finite(transparency, transparency_name);
    }
    std::vector<float> color;
    if (flags & has_color) {
        color = read_floats(reader, 3 * point_count, color_name);
        require_finite(color, color_name);
    }

    file.strands = strands_from_counts(std::move(points), counts, std::move(radius));
    if (flags & has_transparency)
        file.strands.set_attribute(transparency_name, AttributeDomain::Point, 1,
                                   std::move(transparency));
    if (flags & has_color)
        file.strands.set_attribute(color_name, AttributeDomain::Point, 3, std::move(color));
    return file;
}

std::vector<std::byte> write_cyhair(const StrandSet& strands, const CyHairHeader& header) {
    strands.validate();
    constexpr size_t uint32_max = std::numeric_limits<uint32_t>::max();
    constexpr size_t max_points_per_curve = std::numeric_limits<uint16_t>::max() + size_t{1};
    if (strands.curve_count() > uint32_max || strands.point_count() > uint32_max)
        throw Error(".hair stores at most " + std::to_string(uint32_max) +
                    " strands and points, got " + std::to_string(strands.curve_count()) +
                    " strands and " + std::to_string(strands.point_count()) + " points");
    if (header.info.size() > cyhair_info_bytes ||
        header.info.find('\0') != std::string::npos)
        throw Error(".hair info text must have at most " + std::to_string(cyhair_info_bytes) +
                    " bytes and no NUL character");
    const Attribute* transparency = point_attribute(strands, transparency_name, 1);
    const Attribute* color = point_attribute(strands, color_name, 3);

    // One size for all curves lets the header's default segment count replace the array.
    bool same_size = true;
    for (size_t c = 0; c < strands.curve_count(); ++c) {
        if (strands.curve_size(c) != strands.curve_size(0)) same_size = false;
        if (strands.curve_size(c) > max_points_per_curve)
            throw Error("curve " + std::to_string(c) + " has " +
                        std::to_string(strands.curve_size(c)) + " points; .hair stores at most " +
                        std::to_string(max_points_per_curve) + " per curve");
    }
    const bool write_segments = !same_size;
    const uint32_t default_segments =
        same_size && strands.curve_count() > 0 ? static_cast<uint32_t>(strands.curve_size(0) - 1)
                                               : 0;

    uint32_t flags = has_points | has_thickness;
    if (write_segments) flags |= has_segments;
    if (transparency) flags |= has_transparency;
    if (color) flags |= has_color;

    ByteWriter writer;
    writer.reserve(cyhair_header_bytes + 2 * strands.curve_count() + 32 * strands.point_count());
    for (char c : signature) writer.write(static_cast<uint8_t>(c));
    writer.write(static_cast<uint32_t>(strands.curve_count()));
    writer.write(static_cast<uint32_t>(strands.point_count()));
    writer.write(flags);
    writer.write(default_segments);
    writer.write(header.default_thickness);
    writer.write(header.default_transparency);
    for (int k = 0; k < 3; ++k) writer.write(header.default_color[k]);
    writer.write_bytes(std::as_bytes(std::span(header.info.data(), header.info.size())));
    writer.write_zeros(cyhair_info_bytes - header.info.size());

    if (write_segments) {
        std::vector<uint16_t> segments(strands.curve_count());
        for (size_t c = 0; c < segments.size(); ++c)
            segments[c] = static_cast<uint16_t>(strands.curve_size(c) - 1);
        writer.write_array(std::span<const uint16_t>(segments));
    }
    writer.write_array(point_floats(strands.points));
    std::vector<float> thickness(strands.radius.size());
    for (size_t i = 0; i < thickness.size(); ++i) {
        thickness[i] = 2.0f * strands.radius[i];
        if (!std::isfinite(thickness[i]))
            throw Error("radius[" + std::to_string(i) + "] is too large for a .hair thickness");
    }
    writer.write_array(std::span<const float>(thickness));
    if (transparency) writer.write_array(std::span<const float>(transparency->values));
    if (color) writer.write_array(std::span<const float>(color->values));
    return std::move(writer).take();
}

}  // namespace hairlod::io
