// read_tfx either accepts an input or throws hairlod::Error; anything else (a crash, a
// sanitizer report, another exception) is a finding.
#include "fuzz_support.h"
#include "hairlod/core/error.h"
#include "hairlod/io/tfx.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        hairlod::io::read_tfx(hairlod::fuzz::input_bytes(data, size));
    } catch (const hairlod::Error&) {
    }
    return 0;
}
