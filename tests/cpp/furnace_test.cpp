#include "hairlod/bcsdf/furnace.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hairlod::bcsdf {
namespace {

TEST(Furnace, DirectionParametrisation) {
    const glm::dvec3 w = fiber_frame_direction(0.3, 1.2);
    EXPECT_NEAR(w.x, std::sin(0.3), 1e-15);
    EXPECT_NEAR(w.y * w.y + w.z * w.z + w.x * w.x, 1.0, 1e-15);
}

TEST(Furnace, MeasureIntegratesTheSphere) {
    // integral of cos(theta) dw over the sphere = pi^2 (cos^2 theta dtheta dphi).
    const double total = integrate_directions([](const glm::dvec3&) { return 1.0; }, -std::numbers::pi, std::numbers::pi);
    EXPECT_NEAR(total, std::numbers::pi * std::numbers::pi, 1e-8);
    // A lobe that is 1/pi^2 everywhere is a lossless diffuse fibre.
    const double half = integrate_directions([](const glm::dvec3& w) { return w.y < 0.0 ? 2.0 / (std::numbers::pi * std::numbers::pi) : 0.0; },
                                             -std::numbers::pi, std::numbers::pi, {1e-8, 1e-8, 40});
    EXPECT_NEAR(half, 1.0, 1e-5);
}

}  // namespace
}  // namespace hairlod::bcsdf
