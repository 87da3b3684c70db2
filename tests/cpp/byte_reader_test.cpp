#include "hairlod/io/byte_reader.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "io_test_support.h"

namespace hairlod::io {
namespace {

using testing::expect_error_containing;

const std::vector<std::byte> sample_bytes{std::byte{0x01}, std::byte{0x02}, std::byte{0x03},
                                          std::byte{0x04}, std::byte{0x00}, std::byte{0x00},
                                          std::byte{0x80}, std::byte{0x3f}};

TEST(ByteReader, ReadsLittleEndianValues) {
    ByteReader reader(sample_bytes);
    EXPECT_EQ(reader.read<uint32_t>("u32"), 0x04030201u);
    EXPECT_EQ(reader.read<float>("f32"), 1.0f);
    EXPECT_EQ(reader.remaining(), 0u);
}

TEST(ByteReader, ReadsBigEndianValues) {
    ByteReader reader(sample_bytes, ByteOrder::BigEndian);
    EXPECT_EQ(reader.read<uint16_t>("u16"), 0x0102u);
    EXPECT_EQ(reader.read<int16_t>("i16"), 0x0304);
    EXPECT_EQ(reader.position(), 4u);
}

TEST(ByteReader, TruncatedReadNamesWhatAndWhere) {
    ByteReader reader(sample_bytes);
    reader.skip(6, "start");
    expect_error_containing([&] { reader.read<uint32_t>("strand count"); },
                            "strand count: needs 4 bytes at offset 6 but only 2 are left");
    EXPECT_EQ(reader.position(), 6u) << "a failed read must not move the reader";
}

TEST(ByteReader, SkipAndSeekAreBoundsChecked) {
    ByteReader reader(sample_bytes);
    EXPECT_THROW(reader.skip(9, "too far"), Error);
    EXPECT_THROW(reader.seek(9, "too far"), Error);
    reader.seek(8, "end");
    EXPECT_EQ(reader.remaining(), 0u);
    EXPECT_THROW(reader.read<uint8_t>("past end"), Error);
    EXPECT_THROW(reader.read_bytes(SIZE_MAX, "huge"), Error);
}

TEST(ByteReader, EmptyInput) {
    ByteReader reader(std::span<const std::byte>{});
    EXPECT_EQ(reader.size(), 0u);
    EXPECT_THROW(reader.read<uint8_t>("byte"), Error);
}

}  // namespace
}  // namespace hairlod::io
