#include "hairlod/io/tfx.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>

#include "hairlod/io/byte_writer.h"
#include "io_test_support.h"

namespace hairlod::io {
namespace {

using testing::expect_error_containing;

struct TfxLayout {
    uint32_t strands = 2;
    uint32_t vertices_per_strand = 3;
    uint32_t position_offset = tfx_header_bytes;
    uint32_t thickness_offset = 0;
    size_t position_count = 6;
};

// Position i is (i, -i, 2i) with inverse mass 1.
std::vector<std::byte> tfx_bytes(const TfxLayout& layout) {
    ByteWriter writer;
    writer.write(4.0f);
    writer.write(layout.strands);
    writer.write(layout.vertices_per_strand);
    writer.write(layout.position_offset);
    writer.write(uint32_t{0});  // strand UV
    writer.write(uint32_t{0});  // vertex UV
    writer.write(layout.thickness_offset);
    writer.write(uint32_t{0});  // vertex colour
    writer.write_zeros(tfx_header_bytes - writer.size());
    writer.write_zeros(layout.position_offset - tfx_header_bytes);
    for (size_t i = 0; i < layout.position_count; ++i) {
        const auto v = static_cast<float>(i);
        for (float value : {v, -v, 2.0f * v, 1.0f}) writer.write(value);
    }
    return std::move(writer).take();
}

TEST(Tfx, ReadsPositions) {
    const StrandSet strands = read_tfx(tfx_bytes({}), {0.5f});
    EXPECT_EQ(strands.offsets, (std::vector<int64_t>{0, 3, 6}));
    EXPECT_EQ(strands.points[4], glm::vec3(4.0f, -4.0f, 8.0f));
    EXPECT_EQ(strands.radius, std::vector<float>(6, 0.5f));
}

TEST(Tfx, ReadsPositionsAtAnOffset) {
    TfxLayout layout;
    layout.position_offset = tfx_header_bytes + 32;
    layout.thickness_offset = tfx_header_bytes;
    EXPECT_EQ(read_tfx(tfx_bytes(layout)).points[1], glm::vec3(1.0f, -1.0f, 2.0f));
}

TEST(Tfx, RejectsBadHeaders) {
    expect_error_containing([] { read_tfx(std::vector<std::byte>(100)); },
                            "file has 100 bytes, less than the 160-byte .tfx header");
    TfxLayout absurd;
    absurd.strands = 1u << 31;
    absurd.vertices_per_strand = 1u << 31;
    expect_error_containing([&] { read_tfx(tfx_bytes(absurd)); },
                            "header claims 2147483648 strands of 2147483648 vertices at byte 160 "
                            "but the file has only 256 bytes");
    TfxLayout one_vertex;
    one_vertex.vertices_per_strand = 1;
    expect_error_containing([&] { read_tfx(tfx_bytes(one_vertex)); }, "every strand needs at least 2");
    TfxLayout in_header;
    in_header.position_offset = tfx_header_bytes;
    std::vector<std::byte> bytes = tfx_bytes(in_header);
    bytes[12] = std::byte{16};  // position offset 16
    expect_error_containing([&] { read_tfx(bytes); }, "points into the 160-byte header");
    TfxLayout bad_thickness;
    bad_thickness.thickness_offset = 1u << 20;
    expect_error_containing([&] { read_tfx(tfx_bytes(bad_thickness)); },
                            "strand thickness offset 1048576 is outside the data");
}

TEST(Tfx, RejectsNaNPosition) {
    std::vector<std::byte> bytes = tfx_bytes({});
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(bytes.data() + tfx_header_bytes + 16 * 5, &nan, sizeof(nan));
    expect_error_containing([&] { read_tfx(bytes); }, "point 5 is not finite");
}

TEST(Tfx, EveryTruncationIsRejected) {
    testing::expect_truncations_rejected(tfx_bytes({}), [](auto cut) { read_tfx(cut); });
}

}  // namespace
}  // namespace hairlod::io
