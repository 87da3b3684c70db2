// read_cyhair either accepts an input or throws hairlod::Error; what it accepts survives
// write_cyhair and a second read bit for bit, header included.
#include <bit>
#include <cstdlib>
#include <tuple>

#include "fuzz_support.h"
#include "hairlod/core/error.h"
#include "hairlod/io/cyhair.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace hairlod;
    io::CyHairFile file;
    try {
        file = io::read_cyhair(fuzz::input_bytes(data, size));
    } catch (const Error&) {
        return 0;
    }
    const io::CyHairFile again = io::read_cyhair(io::write_cyhair(file.strands, file.header));
    fuzz::require_same_strands(file.strands, again.strands, true);
    const auto bits = [](const io::CyHairHeader& h) {
        return std::make_tuple(std::bit_cast<uint32_t>(h.default_thickness),
                               std::bit_cast<uint32_t>(h.default_transparency),
                               std::bit_cast<uint32_t>(h.default_color.x),
                               std::bit_cast<uint32_t>(h.default_color.y),
                               std::bit_cast<uint32_t>(h.default_color.z), h.info);
    };
    if (bits(file.header) != bits(again.header)) std::abort();
    return 0;
}
