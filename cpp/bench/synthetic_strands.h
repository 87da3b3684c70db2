#pragma once
// Deterministic synthetic hair for benchmarks: wavy strands hanging from a sphere.
#include "hairlod/core/strand_set.h"

namespace hairlod::bench {

StrandSet synthetic_strands(size_t curves, size_t points_per_curve);

}  // namespace hairlod::bench
