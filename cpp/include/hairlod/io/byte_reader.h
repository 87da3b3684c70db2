#pragma once
// ByteReader: bounds-checked reads of a binary file held in memory, with an explicit byte order.
// Every read names what it reads, so a truncated file fails with a message such as
// "points: needs 12 bytes at offset 328 but only 4 are left" instead of reading past the end.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
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
        std::span<const std::byte> source = read_bytes(sizeof(T), what);
        std::array<std::byte, sizeof(T)> raw;
        std::copy(source.begin(), source.end(), raw.begin());
        const bool file_is_little = order_ == ByteOrder::LittleEndian;
        if (file_is_little != (std::endian::native == std::endian::little))
            std::reverse(raw.begin(), raw.end());
        return std::bit_cast<T>(raw);
    }

private:
    std::span<const std::byte> bytes_;
    ByteOrder order_;
    size_t position_ = 0;
};

}  // namespace hairlod::io
