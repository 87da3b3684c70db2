// read_ct2hair_bin either accepts an input or throws hairlod::Error; anything else (a crash, a
// sanitizer report, another exception) is a finding.
#include "fuzz_support.h"
#include "hairlod/core/error.h"
#include "hairlod/io/ct2hair_bin.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        hairlod::io::read_ct2hair_bin(hairlod::fuzz::input_bytes(data, size));
    } catch (const hairlod::Error&) {
    }
    return 0;
}
