#include "hairlod/io/hair_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hairlod/core/strand_metrics.h"
#include "io_test_support.h"

namespace hairlod::io {
namespace {

using testing::expect_error_containing;

// A fresh directory per test, removed afterwards.
class HairFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        directory_ = std::filesystem::temp_directory_path() /
                     ("hairlod_io_" + std::string(info->name()) + "_" +
                      std::to_string(std::hash<std::string>{}(HAIRLOD_SHARED_DATA_DIR)));
        std::filesystem::remove_all(directory_);
        std::filesystem::create_directories(directory_);
    }
    void TearDown() override { std::filesystem::remove_all(directory_); }

    size_t files_in_directory() const {
        return static_cast<size_t>(std::distance(std::filesystem::directory_iterator(directory_),
                                                 std::filesystem::directory_iterator()));
    }

    std::filesystem::path directory_;
};

TEST(HairFormats, FromExtensionCaseInsensitive) {
    EXPECT_EQ(hair_format_from_path("a/b/Bangs.HAIR"), HairFormat::CyHair);
    EXPECT_EQ(hair_format_from_path("x.Data"), HairFormat::UscData);
    EXPECT_EQ(hair_format_from_path("x.bin"), HairFormat::Ct2HairBin);
    EXPECT_EQ(hair_format_from_path("x.PLY"), HairFormat::Ply);
    EXPECT_EQ(hair_format_from_path("x.tfx"), HairFormat::TressFx);
    expect_error_containing([] { hair_format_from_path("hair.obj"); },
                            "hair.obj: unknown hair file extension '.obj'; supported: .hair, "
                            ".data, .bin, .ply, .tfx");
    EXPECT_THROW(hair_format_from_path("no_extension"), Error);
}

TEST(HairFormats, TableListsWritableFormats) {
    size_t writable = 0;
    for (const HairFormatInfo& info : hair_formats()) writable += info.writable;
    EXPECT_EQ(hair_formats().size(), 5u);
    EXPECT_EQ(writable, 2u);
}

TEST_F(HairFileTest, AllBangs100FilesReadToIdenticalCurves) {
    const char* names[] = {"Bangs_100.hair", "Bangs_100.data", "Bangs_100.bin",
                           "Bangs_100_ascii.ply", "Bangs_100_binary.ply"};
    HAIRLOD_SKIP_WITHOUT_SHARED_DATA();
    const std::filesystem::path dir = testing::hairutil_dir();
    const HairFileContents reference = read_hair_file(dir / names[0]);
    EXPECT_EQ(reference.strands.curve_count(), 100u);
    EXPECT_EQ(reference.strands.point_count(), 1165u);
    for (const char* name : names) {
        SCOPED_TRACE(name);
        const HairFileContents contents = read_hair_file(dir / name);
        testing::expect_same_curves(reference.strands, contents.strands);
        EXPECT_EQ(contents.skipped_strands, 0u);
    }
}

TEST_F(HairFileTest, DefaultRadiusOption) {
    HAIRLOD_SKIP_WITHOUT_SHARED_DATA();
    const std::filesystem::path data = testing::hairutil_dir() / "Bangs_100.data";
    const HairFileContents given = read_hair_file(data, {0.02f});
    EXPECT_EQ(given.strands.radius, std::vector<float>(1165, 0.02f));
    const HairFileContents fallback = read_hair_file(data);
    EXPECT_FLOAT_EQ(fallback.strands.radius[0],
                    default_radius_per_diagonal * bounding_box(fallback.strands.points).diagonal());
    expect_error_containing([&] { read_hair_file(data, {-1.0f}); },
                            data.string() + ": default radius must be finite and >= 0");
}

TEST_F(HairFileTest, WritesAndReadsBackHairAndData) {
    const StrandSet strands = testing::sample_strands();
    for (const char* name : {"out.hair", "OUT.DATA"}) {
        const std::filesystem::path path = directory_ / name;
        write_hair_file(path, strands);
        const HairFileContents contents = read_hair_file(path);
        testing::expect_same_curves(strands, contents.strands);
    }
    EXPECT_EQ(read_hair_file(directory_ / "out.hair").strands.radius, strands.radius);
    EXPECT_EQ(files_in_directory(), 2u) << "no temporary file is left behind";
}

TEST_F(HairFileTest, OverwritesAnExistingFile) {
    const std::filesystem::path path = directory_ / "out.data";
    std::ofstream(path) << "old";
    write_hair_file(path, testing::sample_strands());
    EXPECT_EQ(read_hair_file(path).strands.curve_count(), 3u);
}

TEST_F(HairFileTest, FailedWriteLeavesNoFile) {
    StrandSet invalid = testing::sample_strands();
    invalid.radius.pop_back();
    const std::filesystem::path path = directory_ / "bad.hair";
    expect_error_containing([&] { write_hair_file(path, invalid); },
                            path.string() + ": radius has 8 values for 9 points");
    expect_error_containing([&] { write_hair_file(directory_ / "out.ply", testing::sample_strands()); },
                            "writing .ply is not supported; hairlod writes .hair, .data");
    expect_error_containing(
        [&] { write_hair_file(directory_ / "missing_dir" / "x.hair", testing::sample_strands()); },
        "cannot create");
    EXPECT_EQ(files_in_directory(), 0u);
}

TEST_F(HairFileTest, ReadErrorsNameTheFile) {
    const std::filesystem::path missing = directory_ / "missing.hair";
    expect_error_containing([&] { read_hair_file(missing); }, missing.string() + ": no such file");
    expect_error_containing([&] { read_hair_file(directory_ / "dir.hair"); }, "no such file");
    std::filesystem::create_directory(directory_ / "dir.hair");
    expect_error_containing([&] { read_hair_file(directory_ / "dir.hair"); }, "not a regular file");

    const std::filesystem::path bangs = directory_ / "Bangs.hair";
    std::ofstream(bangs, std::ios::binary) << std::string(100, 'x');
    expect_error_containing([&] { read_hair_file(bangs); },
                            bangs.string() + ": file has 100 bytes, less than the 128-byte");
}

TEST(HairBytes, DispatchesByFormat) {
    const StrandSet strands = testing::sample_strands();
    const std::vector<std::byte> data = write_hair_bytes(HairFormat::UscData, strands);
    testing::expect_same_curves(strands, read_hair_bytes(HairFormat::UscData, data).strands);
    EXPECT_THROW(read_hair_bytes(HairFormat::CyHair, data), Error);
    EXPECT_THROW(write_hair_bytes(HairFormat::TressFx, strands), Error);
}

}  // namespace
}  // namespace hairlod::io
