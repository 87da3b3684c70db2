#pragma once
// Brute-force ground truth of the scattering integrals: the white furnace (integral of
// S cos(theta_i) dw_i) and other integrals over incident or outgoing directions, with nested
// adaptive Gauss-Kronrod quadrature in double precision.
#include <numbers>

#include <glm/vec3.hpp>

#include "hairlod/bcsdf/bcsdf.h"
#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {

// The direction of inclination theta (to the normal plane) and azimuth phi in the fibre frame.
glm::dvec3 fiber_frame_direction(double theta, double phi);

// Integral of g(w) cos(theta) dw = g cos^2(theta) dtheta dphi over theta in [-pi/2, pi/2] and
// phi in [phi_begin, phi_end]; g returns double, glm::dvec3 or LobeValues.
template <typename G>
auto integrate_directions(G&& g, double phi_begin, double phi_end, const QuadratureTolerance& tolerance = {}) {
    return integrate_adaptive_2d(
        [&](double theta, double phi) {
            const double c = std::cos(theta);
            return (c * c) * g(fiber_frame_direction(theta, phi));
        },
        -0.5 * std::numbers::pi, 0.5 * std::numbers::pi, phi_begin, phi_end, tolerance);
}

// White furnace of a model seen from wo: integral of S(wi, wo) cos(theta_i) dw_i (RGB). With
// sigma_a = 0 an energy-conserving model gives 1.
glm::dvec3 white_furnace(const FiberBcsdf& bcsdf, const glm::dvec3& wo, const QuadratureTolerance& tolerance = {});

// The same for the Chiang model at one offset h (near field).
glm::dvec3 white_furnace_near_field(const ChiangBcsdf& bcsdf, const glm::dvec3& wo, double h,
                                    const QuadratureTolerance& tolerance = {});

}  // namespace hairlod::bcsdf
