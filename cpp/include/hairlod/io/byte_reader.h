#pragma once
// ByteReader: bounds-checked reads of a binary file held in memory, with an explicit byte order.
// Every read names what it reads, so a truncated file fails with a message such as
// "points: needs 12 bytes at offset 328 but only 4 are left" instead of reading past the end.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

#include "hairlod/core/error.h"

namespace hairlod::io {

enum class ByteOrder { LittleEndian, BigEndian };

class ByteReader {
public:
    explicit ByteReader(std::span<const std::byte> bytes,
                        ByteOrder order = ByteOrder::LittleEndian)
        : bytes_(bytes), order_(order) {}

    size_t size() const { return bytes_.size(); }
    size_t position() const { return position_; }
    size_t remaining() const { return bytes_.size() - position_; }

    // Throws Error unless `count` more bytes are available; `what` names the data for the message.
    void require(size_t count, std::string_view what) const {
        if (count > remaining())
            throw Error(std::string(what) + ": needs " + std::to_string(count) +
                        " bytes at offset " + std::to_string(position_) + " but only " +
                        std::to_string(remaining()) + " are left");
    }

    std::span<const std::byte> read_bytes(size_t count, std::string_view what) {
        require(count, what);
        std::span<const std::byte> result = bytes_.subspan(position_, count);
        position_ += count;
        return result;
    }

    void skip(size_t count, std::string_view what) {
        require(count, what);
        position_ += count;
    }

    void seek(size_t offset, std::string_view what) {
        if (offset > bytes_.size())
            throw Error(std::string(what) + ": offset " + std::to_string(offset) +
                        " is past the end of the file (" + std::to_string(bytes_.size()) +
                        " bytes)");
        position_ = offset;
    }

    template <typename T>
        requires std::is_arithmetic_v<T>
    T read(std::string_view what) {
        T value;
        read_array(std::span<T>(&value, 1), what);
        return value;
    }

    // Reads out.size() values in one copy (the hot path for point arrays).
    template <typename T>
        requires std::is_arithmetic_v<T>
    void read_array(std::span<T> out, std::string_view what) {
        const std::span<const std::byte> source = read_bytes(out.size_bytes(), what);
        if (out.empty()) return;  // memcpy's pointers must not be null, even for 0 bytes
        std::memcpy(out.data(), source.data(), source.size());
        const bool file_is_little = order_ == ByteOrder::LittleEndian;
        if (sizeof(T) > 1 && file_is_little != (std::endian::native == std::endian::little))
            for (T& value : out) value = reversed_bytes(value);
    }

private:
    template <typename T>
    static T reversed_bytes(T value) {
        auto raw = std::bit_cast<std::array<std::byte, sizeof(T)>>(value);
        std::reverse(raw.begin(), raw.end());
        return std::bit_cast<T>(raw);
    }

    std::span<const std::byte> bytes_;
    ByteOrder order_;
    size_t position_ = 0;
};

}  // namespace hairlod::io
