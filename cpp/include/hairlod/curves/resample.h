#pragma once
// Arc-length resampling of strands along their centripetal Catmull-Rom curves.
#include "hairlod/core/strand_set.h"

namespace hairlod {

struct ResampleOptions {
    int points_per_curve = 16;      // K >= 2 output points per curve, the ends included
    int subdivisions_per_segment = 16;  // fine polyline used to measure arc length
};

// Every curve becomes K points equally spaced in arc length along its Catmull-Rom curve; the first
// and last points are the curve's ends. Radius and point attributes are interpolated linearly in
// the curve parameter, curve attributes are copied. A curve of coincident points becomes K copies
// of its first point.
StrandSet resample_strands(const StrandSet& strands, const ResampleOptions& options = {});

}  // namespace hairlod
