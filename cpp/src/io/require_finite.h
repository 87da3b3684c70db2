#pragma once
// Private to the io readers: attribute arrays get the same NaN/Inf check StrandSet::validate
// gives points and radii.
#include <cmath>
#include <span>
#include <string>
#include <string_view>

#include "hairlod/core/error.h"

namespace hairlod::io {

inline void require_finite(std::span<const float> values, std::string_view array_name) {
    for (size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
            throw Error(std::string(array_name) + " value " + std::to_string(i) +
                        " is not finite (NaN or Inf)");
}

}  // namespace hairlod::io
