#pragma once
// ReadOptions: choices a caller makes when reading hair files.
#include <optional>
#include <span>

#include <glm/vec3.hpp>

namespace hairlod::io {

// Radius of the fallback default, as a fraction of the bounding-box diagonal of the points:
// thin enough to read as hair on any model, whatever its units.
inline constexpr float default_radius_per_diagonal = 1e-4f;

struct ReadOptions {
    // Radius given to every point of formats that store no thickness (.data, .bin, .tfx, and .ply
    // without a radius/thickness/width property). When empty, default_radius_per_diagonal times
    // the bounding-box diagonal of all points is used.
    std::optional<float> default_radius;
};

// The radius for points read without thickness; throws Error if options.default_radius is
// negative or not finite.
float resolve_default_radius(const ReadOptions& options, std::span<const glm::vec3> points);

}  // namespace hairlod::io
