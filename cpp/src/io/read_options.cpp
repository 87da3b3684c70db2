#include "hairlod/io/read_options.h"

#include <cmath>
#include <string>

#include "hairlod/core/strand_metrics.h"
#include "hairlod/core/error.h"

namespace hairlod::io {

float resolve_default_radius(const ReadOptions& options, std::span<const glm::vec3> points) {
    if (options.default_radius) {
        const float radius = *options.default_radius;
        if (!std::isfinite(radius) || radius < 0.0f)
            throw Error("default radius must be finite and >= 0, got " + std::to_string(radius));
        return radius;
    }
    const float radius = default_radius_per_diagonal * bounding_box(points).diagonal();
    // Non-finite points give a non-finite diagonal; StrandSet::validate reports those points.
    return std::isfinite(radius) ? radius : 0.0f;
}

}  // namespace hairlod::io
