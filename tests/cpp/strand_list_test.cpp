#include "hairlod/io/strand_list.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>

#include "hairlod/io/byte_writer.h"
#include "io_test_support.h"

namespace hairlod::io {
namespace {

using testing::expect_error_containing;

// A strand list with the given point counts; point i of the file is (i, 2i, 3i) and the extra
// floats are -1.
std::vector<std::byte> strand_list_bytes(const std::vector<int32_t>& counts, int floats_per_point) {
    ByteWriter writer;
    writer.write(static_cast<int32_t>(counts.size()));
    float index = 0.0f;
    for (int32_t count : counts) {
        writer.write(count);
        for (int32_t i = 0; i < count; ++i, index += 1.0f) {
            writer.write(index);
            writer.write(2.0f * index);
            writer.write(3.0f * index);
            for (int k = 3; k < floats_per_point; ++k) writer.write(-1.0f);
        }
    }
    return std::move(writer).take();
}

TEST(StrandList, ReadsPointsAndIgnoresExtraFloats) {
    const StrandListFile file = read_strand_list(strand_list_bytes({2, 3}, 7), 7, {0.5f});
    EXPECT_EQ(file.strands.offsets, (std::vector<int64_t>{0, 2, 5}));
    EXPECT_EQ(file.strands.points[4], glm::vec3(4.0f, 8.0f, 12.0f));
    EXPECT_EQ(file.strands.radius, std::vector<float>(5, 0.5f));
    EXPECT_EQ(file.skipped_strands, 0u);
}

TEST(StrandList, SkipsStrandsWithFewerThanTwoPointsAndCountsThem) {
    const StrandListFile file = read_strand_list(strand_list_bytes({0, 3, 1, 2, 0}, 3), 3, {});
    EXPECT_EQ(file.strands.offsets, (std::vector<int64_t>{0, 3, 5}));
    EXPECT_EQ(file.skipped_strands, 3u);
    // The 1-point strand's point (index 3) is skipped, not joined to a neighbour.
    EXPECT_EQ(file.strands.points[3], glm::vec3(4.0f, 8.0f, 12.0f));
}

TEST(StrandList, EmptyList) {
    const StrandListFile file = read_strand_list(strand_list_bytes({}, 3), 3, {});
    EXPECT_EQ(file.strands.curve_count(), 0u);
}

TEST(StrandList, RejectsAbsurdAndNegativeCounts) {
    ByteWriter absurd;
    absurd.write(std::numeric_limits<int32_t>::max());
    absurd.write_zeros(96);
    expect_error_containing([&] { read_strand_list(std::move(absurd).take(), 3, {}); },
                            "header claims 2147483647 strands but the file has only 100 bytes");

    ByteWriter negative;
    negative.write(int32_t{-5});
    expect_error_containing([&] { read_strand_list(std::move(negative).take(), 3, {}); },
                            "strand count is negative (-5)");

    ByteWriter negative_points;
    negative_points.write(int32_t{1});
    negative_points.write(int32_t{-1});
    expect_error_containing([&] { read_strand_list(std::move(negative_points).take(), 3, {}); },
                            "strand 0 has a negative point count (-1)");

    ByteWriter huge_strand;
    huge_strand.write(int32_t{1});
    huge_strand.write(int32_t{1000000});
    huge_strand.write_zeros(24);
    expect_error_containing([&] { read_strand_list(std::move(huge_strand).take(), 3, {}); },
                            "strand 0 claims 1000000 points but only 24 bytes are left");
}

TEST(StrandList, RejectsTrailingBytes) {
    std::vector<std::byte> bytes = strand_list_bytes({2}, 3);
    bytes.push_back(std::byte{0});
    expect_error_containing([&] { read_strand_list(bytes, 3, {}); },
                            "1 unexpected bytes after the last of 1 strands");
}

TEST(StrandList, RejectsNaNPoint) {
    std::vector<std::byte> bytes = strand_list_bytes({2}, 3);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(bytes.data() + 8 + 12 + 4, &nan, sizeof(nan));  // y of point 1
    expect_error_containing([&] { read_strand_list(bytes, 3, {}); }, "point 1 is not finite");
}

TEST(StrandList, EveryTruncationIsRejected) {
    testing::expect_truncations_rejected(strand_list_bytes({3, 0, 2, 1, 4}, 7), [](auto bytes) {
        read_strand_list(bytes, 7, {});
    });
}

}  // namespace
}  // namespace hairlod::io
