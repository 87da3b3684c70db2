#include "hairlod/io/ply_hair.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>

#include "hairlod/io/usc_data.h"
#include "io_test_support.h"

namespace hairlod::io {
namespace {

using testing::bytes_of;
using testing::expect_error_containing;

template <typename T>
void append_big_endian(std::vector<std::byte>& bytes, T value) {
    auto raw = std::bit_cast<std::array<std::byte, sizeof(T)>>(value);
    if constexpr (std::endian::native == std::endian::little) std::reverse(raw.begin(), raw.end());
    bytes.insert(bytes.end(), raw.begin(), raw.end());
}

const std::string ascii_header =
    "ply\n"
    "format ascii 1.0\n"
    "comment two strands, a list property and a strand element before the vertices\n"
    "element strand 2\n"
    "property uint8 nsegs\n"
    "element vertex 5\n"
    "property float x\n"
    "property double y\n"
    "property int z\n"
    "property list uchar int extra\n"
    "property float thickness\n"
    "element edge 1\n"
    "property int vertex1\n"
    "property int vertex2\n"
    "end_header\n";

const std::string ascii_body =
    "1\n2\n"
    "0 0.5 -1 0 0.2\n"
    "1 1.5 -2 2 7 8 0.4\n"
    "2 2.5 -3 1 9 0.6\r\n"
    "  3\t3.5 -4 0 0.8\n"
    "+4 4.5 -5 0 1.0\n"
    "0 1\n";

TEST(PlyHair, ReadsSyntheticAscii) {
    const StrandSet strands = read_ply_hair(bytes_of(ascii_header + ascii_body));
    EXPECT_EQ(strands.offsets, (std::vector<int64_t>{0, 2, 5}));
    EXPECT_EQ(strands.points[3], glm::vec3(3.0f, 3.5f, -4.0f));
    EXPECT_EQ(strands.points[4], glm::vec3(4.0f, 4.5f, -5.0f));
    // thickness is a diameter
    EXPECT_FLOAT_EQ(strands.radius[1], 0.2f);
    EXPECT_TRUE(strands.attributes.empty());
}

TEST(PlyHair, ReadsAsciiWithoutFinalNewline) {
    std::string text = ascii_header + ascii_body;
    text.pop_back();
    EXPECT_EQ(read_ply_hair(bytes_of(text)).point_count(), 5u);
}

TEST(PlyHair, ReadsSyntheticBigEndianWithColour) {
    std::vector<std::byte> bytes = bytes_of(
        "ply\r\n"
        "format binary_big_endian 1.0\r\n"
        "element vertex 3\r\n"
        "property double x\r\n"
        "property float y\r\n"
        "property short z\r\n"
        "property uchar red\r\n"
        "property uchar green\r\n"
        "property uchar blue\r\n"
        "property float radius\r\n"
        "element strand 1\r\n"
        "property list ushort uint ids\r\n"
        "property uint vertex_count\r\n"
        "end_header\r\n");
    for (int i = 0; i < 3; ++i) {
        append_big_endian(bytes, 1.5 * i);
        append_big_endian(bytes, -0.25f * static_cast<float>(i));
        append_big_endian(bytes, static_cast<int16_t>(-300 * i));
        append_big_endian(bytes, uint8_t{255});
        append_big_endian(bytes, static_cast<uint8_t>(51 * i));
        append_big_endian(bytes, uint8_t{0});
        append_big_endian(bytes, 0.125f);
    }
    append_big_endian(bytes, uint16_t{2});
    append_big_endian(bytes, uint32_t{7});
    append_big_endian(bytes, uint32_t{8});
    append_big_endian(bytes, uint32_t{3});
    const StrandSet strands = read_ply_hair(bytes);
    EXPECT_EQ(strands.offsets, (std::vector<int64_t>{0, 3}));
    EXPECT_EQ(strands.points[2], glm::vec3(3.0f, -0.5f, -600.0f));
    EXPECT_EQ(strands.radius, std::vector<float>(3, 0.125f));
    const Attribute* color = strands.find_attribute("color");
    ASSERT_NE(color, nullptr);
    EXPECT_EQ(color->components, 3);
    EXPECT_EQ(color->values[0], 1.0f);
    EXPECT_FLOAT_EQ(color->values[4], 0.2f);
    testing::expect_truncations_rejected(bytes, [](auto cut) { read_ply_hair(cut); });
}

TEST(PlyHair, AsciiAndBinaryBangsMatchTheDataFile) {
    std::vector<std::byte> ascii, binary, data;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100_ascii.ply", ascii);
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100_binary.ply", binary);
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.data", data);
    const StrandSet from_ascii = read_ply_hair(ascii);
    const StrandSet from_binary = read_ply_hair(binary);
    EXPECT_EQ(from_binary.curve_count(), 100u);
    EXPECT_EQ(from_binary.point_count(), 1165u);
    testing::expect_same_curves(from_ascii, from_binary);
    testing::expect_same_curves(from_binary, read_usc_data(data).strands);
    // hairutil gave the two files different random colours; both must have them.
    EXPECT_NE(from_ascii.find_attribute("color"), nullptr);
    EXPECT_NE(from_binary.find_attribute("color"), nullptr);
}

TEST(PlyHair, ReadsCurly100) {
    std::vector<std::byte> bytes;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Curly_100.ply", bytes);
    const StrandSet strands = read_ply_hair(bytes, {0.01f});
    EXPECT_EQ(strands.curve_count(), 100u);
    EXPECT_EQ(strands.point_count(), 2528u);
    EXPECT_EQ(strands.radius.front(), 0.01f);
}

TEST(PlyHair, EveryTruncationIsRejected) {
    std::vector<std::byte> binary, ascii;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100_binary.ply", binary);
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100_ascii.ply", ascii);
    testing::expect_truncations_rejected(binary, [](auto cut) { read_ply_hair(cut); });
    // Cutting into the last ascii number leaves a shorter valid number; stop before it.
    testing::expect_truncations_rejected(ascii, [](auto cut) { read_ply_hair(cut); },
                                         ascii.size() - 16);
}

struct BadPly {
    std::string text;
    std::string message;
};

class PlyHairRejects : public ::testing::TestWithParam<BadPly> {};

TEST_P(PlyHairRejects, WithAClearMessage) {
    expect_error_containing([&] { read_ply_hair(bytes_of(GetParam().text)); }, GetParam().message);
}

const std::string vertex_xyz =
    "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n";
const std::string strand_nsegs = "element strand 1\nproperty int nsegs\n";
const std::string ascii_start = "ply\nformat ascii 1.0\n";
const std::string binary_start = "ply\nformat binary_little_endian 1.0\n";

INSTANTIATE_TEST_SUITE_P(
    PlyHair, PlyHairRejects,
    ::testing::Values(
        BadPly{"", "header has no end_header line"},
        BadPly{"obj\nformat ascii 1.0\nend_header\n", "not a PLY file"},
        BadPly{"ply\nend_header\n", "header has no format line"},
        BadPly{"ply\nformat ascii 2.0\nend_header\n", "expected 'format <type> 1.0'"},
        BadPly{"ply\nformat utf8 1.0\nend_header\n", "unknown format 'utf8'"},
        BadPly{ascii_start + "property float x\nend_header\n", "property before any element"},
        BadPly{ascii_start + "element vertex -1\nend_header\n", "not a non-negative integer"},
        BadPly{ascii_start + "element vertex 1\nproperty float128 x\nend_header\n",
               "unknown property type 'float128'"},
        BadPly{ascii_start + "element vertex 1\nproperty list float int x\nend_header\n",
               "list size type must be an integer type"},
        BadPly{ascii_start + "element vertex 1\nproperty float x\nproperty float x\nend_header\n",
               "has property 'x' twice"},
        BadPly{ascii_start + "banana\nend_header\n", "unknown keyword 'banana'"},
        BadPly{ascii_start + strand_nsegs + "end_header\n1\n", "no 'vertex' element"},
        BadPly{ascii_start + vertex_xyz + "end_header\n0 0 0 1 1 1\n", "no 'strand' element"},
        BadPly{ascii_start + "element vertex 2\nproperty float x\nproperty float y\n" +
                   strand_nsegs + "end_header\n0 0 1 1 1\n",
               "element 'vertex' has no property 'z'"},
        BadPly{ascii_start + vertex_xyz + "property uchar red\n" + strand_nsegs + "end_header\n",
               "needs all of red, green, blue"},
        BadPly{ascii_start + vertex_xyz + "element strand 1\nproperty float nsegs\nend_header\n",
               "must be an integer"},
        BadPly{ascii_start + vertex_xyz + "element strand 1\nproperty int count\nend_header\n",
               "none of the properties nsegs, nverts, vertex_count"},
        BadPly{ascii_start + vertex_xyz + strand_nsegs + "end_header\n0 0 0 1 1 1\n2\n",
               "strands need more points than the 2 vertices"},
        BadPly{ascii_start + vertex_xyz + "element strand 2\nproperty int nsegs\nend_header\n"
                   "0 0 0 1 1 1\n1 0\n",
               "strand 1 has 1 point(s)"},
        BadPly{ascii_start + vertex_xyz + strand_nsegs + "end_header\n0 0 0 1 nan 1\n1\n",
               "point 1 is not finite"},
        BadPly{ascii_start + vertex_xyz + strand_nsegs + "end_header\n0 0 0 1 1 1\n1.5\n",
               "'1.5' at body offset 12 is not a valid integer"},
        BadPly{ascii_start + vertex_xyz + strand_nsegs + "end_header\n0 0 0 1 1 1\n1\n7\n",
               "unexpected text after the last element"},
        BadPly{ascii_start + vertex_xyz + strand_nsegs + "end_header\n0 0 0 1 1 1\n",
               "header claims 1 strand elements but only 13 bytes follow the header"},
        BadPly{ascii_start + vertex_xyz + strand_nsegs + "end_header\n0 0 0 1 1 1\n\n\n\n",
               "file ends before the last value"},
        BadPly{ascii_start + "element vertex 2147483648\nproperty float x\nproperty float y\n"
                   "property float z\n" + strand_nsegs + "end_header\n0 0 0 1 1 1\n1\n",
               "header claims 2147483648 vertex elements but only"},
        BadPly{binary_start + vertex_xyz + strand_nsegs + "element edge 1\n"
                   "property list int int ids\nend_header\n" + std::string(24, '\0') +
                   std::string("\x01\x00\x00\x00", 4) + std::string("\xff\xff\xff\x7f", 4),
               "list claims 2147483647 items"},
        BadPly{binary_start + vertex_xyz + strand_nsegs + "element edge 1\n"
                   "property list int int ids\nend_header\n" + std::string(24, '\0') +
                   std::string("\x01\x00\x00\x00", 4) + std::string("\xff\xff\xff\xff", 4),
               "list size -1.000000 is negative"},
        BadPly{binary_start + vertex_xyz + strand_nsegs + "end_header\n" + std::string(24, '\0') +
                   std::string("\x01\x00\x00\x00", 4) + "x",
               "1 unexpected bytes after the last element"}));

}  // namespace
}  // namespace hairlod::io
