#pragma once
// ByteWriter: appends little-endian values to a growing buffer, the byte order of every format
// hairlod writes. Files are assembled in memory first so a failure never leaves half a file.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

namespace hairlod::io {

class ByteWriter {
public:
    void reserve(size_t count) { bytes_.reserve(count); }

    template <typename T>
        requires std::is_arithmetic_v<T>
    void write(T value) {
        auto raw = std::bit_cast<std::array<std::byte, sizeof(T)>>(value);
        if constexpr (std::endian::native == std::endian::big) std::reverse(raw.begin(), raw.end());
        // Grown and copied into, not insert(): GCC 14 warns falsely (-Warray-bounds) on a
        // one-byte range insert.
        const size_t at = bytes_.size();
        bytes_.resize(at + raw.size());
        std::copy(raw.begin(), raw.end(), bytes_.begin() + static_cast<std::ptrdiff_t>(at));
    }

    // Writes all values in one copy on little-endian hosts (the hot path for point arrays).
    template <typename T>
        requires std::is_arithmetic_v<T>
    void write_array(std::span<const T> values) {
        if constexpr (std::endian::native == std::endian::little)
            write_bytes(std::as_bytes(values));
        else
            for (T value : values) write(value);
    }

    void write_bytes(std::span<const std::byte> bytes) {
        bytes_.insert(bytes_.end(), bytes.begin(), bytes.end());
    }

    void write_zeros(size_t count) { bytes_.resize(bytes_.size() + count, std::byte{0}); }

    size_t size() const { return bytes_.size(); }
    std::vector<std::byte> take() && { return std::move(bytes_); }

private:
    std::vector<std::byte> bytes_;
};

}  // namespace hairlod::io
