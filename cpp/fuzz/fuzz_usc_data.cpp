// read_usc_data either accepts an input or throws hairlod::Error; what it accepts survives
// write_usc_data and a second read unchanged.
#include <cstdlib>

#include "fuzz_support.h"
#include "hairlod/core/error.h"
#include "hairlod/io/usc_data.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace hairlod;
    io::StrandListFile file;
    try {
        file = io::read_usc_data(fuzz::input_bytes(data, size));
    } catch (const Error&) {
        return 0;
    }
    // .data stores no radius: the second read derives it again, so only the curves are compared.
    const io::StrandListFile again = io::read_usc_data(io::write_usc_data(file.strands));
    fuzz::require_same_strands(file.strands, again.strands, false);
    if (again.skipped_strands != 0) std::abort();
    return 0;
}
