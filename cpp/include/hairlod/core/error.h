#pragma once
// One exception type for bad input anywhere in the core: malformed files, invalid strand data,
// out-of-range parameters. The message names what is wrong; Python sees it as ValueError.
#include <stdexcept>
#include <string>

namespace hairlod {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace hairlod
