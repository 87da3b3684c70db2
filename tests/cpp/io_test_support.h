#pragma once
// Helpers shared by the io tests: shared data files, byte buffers, truncation sweeps, strand
// comparison.
#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hairlod/core/error.h"
#include "hairlod/core/strand_set.h"

namespace hairlod::io::testing {

inline std::filesystem::path hairutil_dir() {
    return std::filesystem::path(HAIRLOD_SHARED_DATA_DIR) / "hairutil";
}

inline bool hairutil_present() { return std::filesystem::is_directory(hairutil_dir()); }

// Loads ../shared/data/hairutil/<name>; fails the test when the file cannot be read.
inline void load_hairutil_file(const std::string& name, std::vector<std::byte>& bytes) {
    const std::filesystem::path path = hairutil_dir() / name;
    ASSERT_TRUE(std::filesystem::is_regular_file(path)) << "test data " << path << " is missing";
    std::ifstream stream(path, std::ios::binary);
    const auto size = std::filesystem::file_size(path);
    bytes.resize(size);
    stream.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
    ASSERT_EQ(static_cast<std::uintmax_t>(stream.gcount()), size) << "cannot read " << path;
}

}  // namespace hairlod::io::testing

// The shared files live outside the repository (../shared/data); a clone without that
// folder skips these tests with a message saying so, never passes them silently. Macros because
// GTEST_SKIP must return from the test body itself.
#define HAIRLOD_SKIP_WITHOUT_SHARED_DATA()                                                      \
    if (!::hairlod::io::testing::hairutil_present())                                            \
    GTEST_SKIP() << "shared test data " << ::hairlod::io::testing::hairutil_dir()             \
                 << " is absent: clone the repository next to ../shared to run this test"

#define HAIRLOD_LOAD_HAIRUTIL_FILE(name, bytes)                                              \
    do {                                                                                      \
        HAIRLOD_SKIP_WITHOUT_SHARED_DATA();                                                   \
        ASSERT_NO_FATAL_FAILURE(::hairlod::io::testing::load_hairutil_file(name, bytes));     \
    } while (false)

namespace hairlod::io::testing {

inline std::vector<std::byte> bytes_of(std::string_view text) {
    const auto* data = reinterpret_cast<const std::byte*>(text.data());
    return {data, data + text.size()};
}

// Every length below 512, then about 400 lengths spread over the rest (all but the full size).
inline std::vector<size_t> truncation_lengths(size_t size) {
    std::vector<size_t> lengths;
    const size_t step = size > 512 ? std::max<size_t>(1, (size - 512) / 400) : 1;
    for (size_t length = 0; length < size; length += length < 512 ? 1 : step)
        lengths.push_back(length);
    if (size > 0) lengths.push_back(size - 1);
    return lengths;
}

// Checks that `read` throws hairlod::Error for every truncation (up to `max_length`) of `bytes`.
inline void expect_truncations_rejected(
    std::span<const std::byte> bytes,
    const std::function<void(std::span<const std::byte>)>& read,
    size_t max_length = static_cast<size_t>(-1)) {
    for (size_t length : truncation_lengths(bytes.size())) {
        if (length > max_length) break;
        // A copy, so that AddressSanitizer sees reads past the cut.
        const std::vector<std::byte> cut(bytes.begin(), bytes.begin() + length);
        EXPECT_THROW(read(cut), Error) << "truncated to " << length << " of " << bytes.size()
                                       << " bytes";
    }
}

// Expects `read` to throw hairlod::Error whose message contains `fragment`.
template <typename Read>
void expect_error_containing(Read&& read, std::string_view fragment) {
    try {
        read();
        ADD_FAILURE() << "expected hairlod::Error containing '" << fragment << "'";
    } catch (const Error& error) {
        EXPECT_NE(std::string_view(error.what()).find(fragment), std::string_view::npos)
            << "message: " << error.what() << "\nexpected to contain: " << fragment;
    }
}

inline void expect_same_curves(const StrandSet& a, const StrandSet& b) {
    ASSERT_EQ(a.offsets, b.offsets);
    ASSERT_EQ(a.points.size(), b.points.size());
    for (size_t i = 0; i < a.points.size(); ++i)
        ASSERT_EQ(a.points[i], b.points[i]) << "point " << i;
}

inline void expect_identical(const StrandSet& a, const StrandSet& b) {
    expect_same_curves(a, b);
    EXPECT_EQ(a.radius, b.radius);
    ASSERT_EQ(a.attributes.size(), b.attributes.size());
    for (const auto& [name, attribute] : a.attributes) {
        const Attribute* other = b.find_attribute(name);
        ASSERT_NE(other, nullptr) << "attribute " << name;
        EXPECT_EQ(attribute.domain, other->domain) << name;
        EXPECT_EQ(attribute.components, other->components) << name;
        EXPECT_EQ(attribute.values, other->values) << name;
    }
}

// Three curves of 2, 3 and 4 points with distinct values, for round trips.
inline StrandSet sample_strands() {
    StrandSet strands;
    float value = 0.25f;
    for (int size : {2, 3, 4}) {
        std::vector<glm::vec3> curve;
        std::vector<float> radius;
        for (int i = 0; i < size; ++i) {
            curve.emplace_back(value, -2.0f * value, 1e6f * value);
            radius.push_back(0.01f * value);
            value += 1.375f;
        }
        strands.add_curve(curve, radius);
    }
    return strands;
}

}  // namespace hairlod::io::testing
