#include "hairlod/io/byte_writer.h"

#include <gtest/gtest.h>

#include <cstdint>

#include "hairlod/io/byte_reader.h"

namespace hairlod::io {
namespace {

TEST(ByteWriter, WritesLittleEndian) {
    ByteWriter writer;
    writer.write(uint32_t{0x04030201});
    writer.write(int16_t{-2});
    const std::vector<std::byte> bytes = std::move(writer).take();
    ASSERT_EQ(bytes.size(), 6u);
    EXPECT_EQ(bytes[0], std::byte{0x01});
    EXPECT_EQ(bytes[3], std::byte{0x04});
    EXPECT_EQ(bytes[4], std::byte{0xfe});
    EXPECT_EQ(bytes[5], std::byte{0xff});
}

TEST(ByteWriter, RoundTripsThroughByteReader) {
    ByteWriter writer;
    writer.write(-1.5f);
    writer.write(2.25);
    writer.write_zeros(3);
    writer.write(uint8_t{7});
    EXPECT_EQ(writer.size(), 4u + 8u + 3u + 1u);
    const std::vector<std::byte> bytes = std::move(writer).take();
    ByteReader reader(bytes);
    EXPECT_EQ(reader.read<float>("f"), -1.5f);
    EXPECT_EQ(reader.read<double>("d"), 2.25);
    reader.skip(3, "zeros");
    EXPECT_EQ(reader.read<uint8_t>("u8"), 7u);
}

}  // namespace
}  // namespace hairlod::io
