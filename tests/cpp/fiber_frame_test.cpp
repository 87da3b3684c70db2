#include "hairlod/bcsdf/fiber_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hairlod::bcsdf {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(FiberFrame, DirectionAngles) {
    const FiberDirection d = fiber_direction({0.5, 0.0, std::sqrt(0.75)});
    EXPECT_NEAR(d.theta, kPi / 6.0, 1e-12);
    EXPECT_NEAR(d.phi, kPi / 2.0, 1e-12);
    // Not normalised, and the degenerate zero vector.
    EXPECT_NEAR(fiber_direction({2.0, 0.0, 0.0}).theta, kPi / 2.0, 1e-12);
    EXPECT_NEAR(fiber_direction({0.0, 0.0, 0.0}).cos_theta, 1.0, 1e-12);
}

TEST(FiberFrame, HalfAnglesAndWrap) {
    const FiberDirection wi = fiber_direction({std::sin(0.2), std::cos(0.2) * std::cos(3.0), std::cos(0.2) * std::sin(3.0)});
    const FiberDirection wo = fiber_direction({std::sin(-0.4), std::cos(0.4) * std::cos(-3.0), std::cos(0.4) * std::sin(-3.0)});
    const HalfAngles a = half_angles(wi, wo);
    EXPECT_NEAR(a.theta_h, -0.1, 1e-12);
    EXPECT_NEAR(a.theta_d, -0.3, 1e-12);
    EXPECT_NEAR(a.phi, 2.0 * kPi - 6.0, 1e-12);  // -6 wrapped into [-pi, pi]
    EXPECT_NEAR(std::cos(2.0 * a.phi_h), std::cos(2.0 * kPi), 1e-12);
    EXPECT_NEAR(std::abs(wrap_angle(3.0 * kPi)), kPi, 1e-12);
    EXPECT_NEAR(wrap_angle(-7.0), 2.0 * kPi - 7.0, 1e-12);
}

TEST(FiberFrame, Fresnel) {
    const double eta = 1.55;
    const double r0 = (eta - 1.0) / (eta + 1.0);
    EXPECT_NEAR(fresnel_dielectric(1.0, eta), r0 * r0, 1e-14);
    EXPECT_NEAR(fresnel_dielectric(0.0, eta), 1.0, 1e-14);
    // Brewster's angle: the p-polarised reflectance vanishes, F = r_s^2 / 2.
    const double brewster = std::atan(eta);
    const double cos_t = std::cos(kPi / 2.0 - brewster);
    const double r_s = (std::cos(brewster) - eta * cos_t) / (std::cos(brewster) + eta * cos_t);
    EXPECT_NEAR(fresnel_dielectric(std::cos(brewster), eta), 0.5 * r_s * r_s, 1e-14);
}

TEST(FiberFrame, BravaisIndex) {
    EXPECT_NEAR(bravais_index(1.55, 0.0, 1.0), 1.55, 1e-14);
    const double theta = 0.7;
    EXPECT_NEAR(bravais_index(1.55, std::sin(theta), std::cos(theta)),
                std::sqrt(1.55 * 1.55 - std::sin(theta) * std::sin(theta)) / std::cos(theta), 1e-14);
    EXPECT_TRUE(std::isfinite(bravais_index(1.55, 1.0, 0.0)));
}

}  // namespace
}  // namespace hairlod::bcsdf
