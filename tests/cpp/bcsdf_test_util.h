#pragma once
// Helpers shared by the bcsdf tests: random directions with a fixed seed, grazing corners, one set of
// circular-Gaussian tables.
#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include <glm/vec3.hpp>

#include "hairlod/bcsdf/circular_gaussian.h"
#include "hairlod/bcsdf/furnace.h"

namespace hairlod::bcsdf::test {

// Uniform on the sphere.
inline glm::dvec3 random_direction(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double x = u(rng);
    const double phi = std::numbers::pi * u(rng);
    const double r = std::sqrt(std::max(0.0, 1.0 - x * x));
    return {x, r * std::cos(phi), r * std::sin(phi)};
}

// Directions at and next to the poles theta = +-pi/2 and in the normal plane.
inline std::vector<glm::dvec3> corner_directions() {
    std::vector<glm::dvec3> corners;
    for (double theta : {-0.5 * std::numbers::pi, -0.5 * std::numbers::pi + 1e-7, -1.2, 0.0, 1.2,
                         0.5 * std::numbers::pi - 1e-7, 0.5 * std::numbers::pi})
        for (double phi : {-std::numbers::pi, -0.5 * std::numbers::pi, 0.0, 1e-9, 0.5 * std::numbers::pi, std::numbers::pi})
            corners.push_back(fiber_frame_direction(theta, phi));
    return corners;
}

inline bool finite_non_negative(const glm::dvec3& v) {
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(v[c]) || v[c] < 0.0) return false;
    return true;
}

// The circular-Gaussian tables, built once per test program (they take a moment).
inline std::shared_ptr<const CircularGaussianTables> shared_circular_gaussian_tables() {
    static const auto tables = std::make_shared<const CircularGaussianTables>(circular_gaussian_tables());
    return tables;
}

}  // namespace hairlod::bcsdf::test
