#include "hairlod/io/usc_data.h"

#include <gtest/gtest.h>

#include "io_test_support.h"

namespace hairlod::io {
namespace {


TEST(UscData, ReadsBangs100) {
    std::vector<std::byte> bytes;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.data", bytes);
    const StrandListFile file = read_usc_data(bytes);
    EXPECT_EQ(file.strands.curve_count(), 100u);
    EXPECT_EQ(file.strands.point_count(), 1165u);
    EXPECT_EQ(file.skipped_strands, 0u);
    EXPECT_GT(file.strands.radius[0], 0.0f) << "radius falls back to a fraction of the diagonal";
}

TEST(UscData, RoundTripIsExact) {
    const StrandSet strands = testing::sample_strands();
    const StrandListFile file = read_usc_data(write_usc_data(strands), {0.125f});
    testing::expect_same_curves(strands, file.strands);
    EXPECT_EQ(file.strands.radius, std::vector<float>(strands.point_count(), 0.125f));
}

TEST(UscData, RoundTripOfBangs100IsByteExact) {
    std::vector<std::byte> bytes;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.data", bytes);
    EXPECT_EQ(write_usc_data(read_usc_data(bytes).strands), bytes);
}

TEST(UscData, WriterRejectsInvalidStrands) {
    StrandSet strands = testing::sample_strands();
    strands.offsets.back() += 1;
    EXPECT_THROW(write_usc_data(strands), Error);
}

TEST(UscData, EveryTruncationIsRejected) {
    std::vector<std::byte> bytes;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.data", bytes);
    testing::expect_truncations_rejected(bytes, [](auto cut) { read_usc_data(cut); });
}

}  // namespace
}  // namespace hairlod::io
