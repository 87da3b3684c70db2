#include "hairlod/io/cyhair.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>

#include "hairlod/io/byte_writer.h"
#include "io_test_support.h"

namespace hairlod::io {
namespace {

using testing::expect_error_containing;

constexpr size_t flags_offset = 12;
constexpr size_t segments_flag = 1;

// A 128-byte header with the given counts and flags and default segments 1.
std::vector<std::byte> header_bytes(uint32_t hairs, uint32_t points, uint32_t flags) {
    ByteWriter writer;
    writer.reserve(cyhair_header_bytes);
    for (char c : std::string_view("HAIR")) writer.write(static_cast<uint8_t>(c));
    writer.write(hairs);
    writer.write(points);
    writer.write(flags);
    writer.write(uint32_t{1});
    writer.write_zeros(cyhair_header_bytes - writer.size());
    return std::move(writer).take();
}

uint32_t flags_of(const std::vector<std::byte>& bytes) {
    uint32_t flags;
    std::memcpy(&flags, bytes.data() + flags_offset, sizeof(flags));
    return flags;
}

StrandSet strands_with_all_attributes() {
    StrandSet strands = testing::sample_strands();
    std::vector<float> transparency, color;
    for (size_t i = 0; i < strands.point_count(); ++i) {
        transparency.push_back(0.1f * static_cast<float>(i));
        for (int k = 0; k < 3; ++k) color.push_back(0.01f * static_cast<float>(3 * i + k));
    }
    strands.set_attribute("transparency", AttributeDomain::Point, 1, transparency);
    strands.set_attribute("color", AttributeDomain::Point, 3, color);
    return strands;
}

TEST(CyHair, ReadsBangs100) {
    std::vector<std::byte> bytes;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.hair", bytes);
    const CyHairFile file = read_cyhair(bytes);
    EXPECT_EQ(file.strands.curve_count(), 100u);
    EXPECT_EQ(file.strands.point_count(), 1165u);
    // No thickness array: the default thickness 1 is a diameter.
    EXPECT_EQ(file.header.default_thickness, 1.0f);
    EXPECT_EQ(file.strands.radius, std::vector<float>(1165, 0.5f));
    EXPECT_TRUE(file.strands.attributes.empty()) << "header defaults are not attributes";
}

TEST(CyHair, RoundTripWithAllArraysIsExact) {
    const StrandSet strands = strands_with_all_attributes();
    CyHairHeader header;
    header.default_thickness = 0.75f;
    header.default_transparency = 0.5f;
    header.default_color = {0.1f, 0.2f, 0.3f};
    header.info = "written by the hairlod io tests";
    const std::vector<std::byte> bytes = write_cyhair(strands, header);
    EXPECT_EQ(flags_of(bytes), 0b11111u);
    const CyHairFile file = read_cyhair(bytes);
    testing::expect_identical(strands, file.strands);
    EXPECT_EQ(file.header.default_thickness, header.default_thickness);
    EXPECT_EQ(file.header.default_transparency, header.default_transparency);
    EXPECT_EQ(file.header.default_color, header.default_color);
    EXPECT_EQ(file.header.info, header.info);
}

TEST(CyHair, EqualCurveSizesOmitTheSegmentsArray) {
    StrandSet strands;
    for (float x : {0.0f, 1.0f, 2.0f})
        strands.add_curve(std::vector<glm::vec3>{{x, 0, 0}, {x, 1, 0}, {x, 2, 0}},
                          std::vector<float>{0.5f, 0.25f, 0.125f});
    const std::vector<std::byte> bytes = write_cyhair(strands);
    EXPECT_EQ(flags_of(bytes) & segments_flag, 0u);
    EXPECT_EQ(bytes.size(), cyhair_header_bytes + 9 * 16);
    testing::expect_identical(strands, read_cyhair(bytes).strands);
}

TEST(CyHair, FullInfoTextRoundTrips) {
    CyHairHeader header;
    header.info = std::string(cyhair_info_bytes, 'i');
    EXPECT_EQ(read_cyhair(write_cyhair(testing::sample_strands(), header)).header.info, header.info);
}

// fuzz_cyhair found undefined behaviour here (a member access through the null data() of the
// empty point array, reported by UBSan); the fuzz build of this test guards it.
TEST(CyHair, EmptyStrandSetRoundTrips) {
    EXPECT_EQ(read_cyhair(write_cyhair(StrandSet{})).strands.curve_count(), 0u);
}

TEST(CyHair, WriterRejectsWhatTheFormatCannotHold) {
    CyHairHeader long_info;
    long_info.info = std::string(cyhair_info_bytes + 1, 'i');
    EXPECT_THROW(write_cyhair(testing::sample_strands(), long_info), Error);

    StrandSet curve_color = testing::sample_strands();
    curve_color.set_attribute("color", AttributeDomain::Curve, 3, std::vector<float>(9, 0.5f));
    expect_error_containing([&] { write_cyhair(curve_color); },
                            "attribute 'color' must be a point attribute with 3 component(s)");

    StrandSet long_curve;
    long_curve.add_curve(std::vector<glm::vec3>(70000, glm::vec3(0.0f)));
    long_curve.add_curve(std::vector<glm::vec3>(2, glm::vec3(0.0f)));
    expect_error_containing([&] { write_cyhair(long_curve); }, "curve 0 has 70000 points");

    StrandSet huge_radius = testing::sample_strands();
    huge_radius.radius[1] = std::numeric_limits<float>::max();
    EXPECT_THROW(write_cyhair(huge_radius), Error);
}

TEST(CyHair, RejectsAbsurdCountsBeforeAllocating) {
    std::vector<std::byte> bytes = header_bytes(1u << 31, 0, 0b11);
    bytes.resize(160);
    expect_error_containing([&] { read_cyhair(bytes); },
                            "header claims 2147483648 strands and 0 points (4294967424 bytes) "
                            "but the file has only 160 bytes");
    // Without a segments array the default segment count must account for every point.
    expect_error_containing([&] { read_cyhair(header_bytes(UINT32_MAX, 0, 0b10)); },
                            "4294967295 strands of 1 default segments need 8589934590 points");
}

TEST(CyHair, RejectsShortFilesAndBadSignature) {
    expect_error_containing([] { read_cyhair(std::vector<std::byte>(100)); },
                            "file has 100 bytes, less than the 128-byte .hair header");
    std::vector<std::byte> bytes = header_bytes(0, 0, 0b10);
    bytes[0] = std::byte{'X'};
    expect_error_containing([&] { read_cyhair(bytes); }, "not a .hair file");
    expect_error_containing([] { read_cyhair(header_bytes(0, 0, 0b1)); }, "no points array");
}

TEST(CyHair, RejectsInconsistentCounts) {
    // Segments say 2 + 3 points, header says 4.
    ByteWriter writer;
    writer.write_bytes(header_bytes(2, 4, 0b11));
    writer.write(uint16_t{1});
    writer.write(uint16_t{2});
    writer.write_zeros(4 * 12);
    expect_error_containing([&] { read_cyhair(std::move(writer).take()); },
                            "segments array adds up to 5 points but the header claims 4");

    ByteWriter zero_segments;
    zero_segments.write_bytes(header_bytes(2, 3, 0b11));
    zero_segments.write(uint16_t{0});
    zero_segments.write(uint16_t{1});
    zero_segments.write_zeros(3 * 12);
    expect_error_containing([&] { read_cyhair(std::move(zero_segments).take()); },
                            "strand 0 has 0 segments");

    std::vector<std::byte> trailing = write_cyhair(testing::sample_strands());
    trailing.push_back(std::byte{0});
    expect_error_containing([&] { read_cyhair(trailing); }, "but the file has");
}

TEST(CyHair, RejectsNonFiniteValues) {
    const StrandSet strands = strands_with_all_attributes();
    const std::vector<std::byte> good = write_cyhair(strands);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const size_t points_offset = cyhair_header_bytes + 2 * strands.curve_count();
    const size_t n = strands.point_count();
    const struct {
        size_t offset;
        const char* message;
    } cases[] = {
        {points_offset + 12 * 2 + 4, "point 2 is not finite"},
        {points_offset + 12 * n + 4 * 3, "radius[3] is not finite"},
        {points_offset + 16 * n + 4 * 4, "transparency value 4 is not finite"},
        {points_offset + 20 * n + 4 * 5, "color value 5 is not finite"},
    };
    for (const auto& c : cases) {
        std::vector<std::byte> bytes = good;
        std::memcpy(bytes.data() + c.offset, &nan, sizeof(nan));
        expect_error_containing([&] { read_cyhair(bytes); }, c.message);
    }
}

TEST(CyHair, EveryTruncationIsRejected) {
    std::vector<std::byte> bangs;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.hair", bangs);
    testing::expect_truncations_rejected(bangs, [](auto cut) { read_cyhair(cut); });
    testing::expect_truncations_rejected(write_cyhair(strands_with_all_attributes()),
                                         [](auto cut) { read_cyhair(cut); });
}

}  // namespace
}  // namespace hairlod::io
