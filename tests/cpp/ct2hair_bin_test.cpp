#include "hairlod/io/ct2hair_bin.h"

#include <gtest/gtest.h>

#include "hairlod/io/usc_data.h"
#include "io_test_support.h"

namespace hairlod::io {
namespace {


TEST(Ct2HairBin, ReadsBangs100LikeTheDataFile) {
    std::vector<std::byte> bin, data;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.bin", bin);
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.data", data);
    const StrandListFile file = read_ct2hair_bin(bin);
    EXPECT_EQ(file.strands.curve_count(), 100u);
    EXPECT_EQ(file.strands.point_count(), 1165u);
    testing::expect_same_curves(file.strands, read_usc_data(data).strands);
}

TEST(Ct2HairBin, ReadsBangs20) {
    std::vector<std::byte> bytes;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_20.bin", bytes);
    const StrandListFile file = read_ct2hair_bin(bytes, {0.5f});
    EXPECT_EQ(file.strands.curve_count(), 20u);
    EXPECT_EQ(file.strands.point_count(), 235u);
    EXPECT_EQ(file.strands.radius.front(), 0.5f);
}

TEST(Ct2HairBin, DataFileIsNotABinFile) {
    std::vector<std::byte> data;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_100.data", data);
    EXPECT_THROW(read_ct2hair_bin(data), Error);
}

TEST(Ct2HairBin, EveryTruncationIsRejected) {
    std::vector<std::byte> bytes;
    HAIRLOD_LOAD_HAIRUTIL_FILE("Bangs_20.bin", bytes);
    testing::expect_truncations_rejected(bytes, [](auto cut) { read_ct2hair_bin(cut); });
}

}  // namespace
}  // namespace hairlod::io
