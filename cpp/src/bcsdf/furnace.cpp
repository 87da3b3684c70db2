#include "hairlod/bcsdf/furnace.h"

#include <cmath>

namespace hairlod::bcsdf {

glm::dvec3 fiber_frame_direction(double theta, double phi) {
    const double c = std::cos(theta);
    return {std::sin(theta), c * std::cos(phi), c * std::sin(phi)};
}

glm::dvec3 white_furnace(const FiberBcsdf& bcsdf, const glm::dvec3& wo, const QuadratureTolerance& tolerance) {
    return integrate_directions([&](const glm::dvec3& wi) { return bcsdf.eval(wi, wo); }, -std::numbers::pi,
                                std::numbers::pi, tolerance);
}

glm::dvec3 white_furnace_near_field(const ChiangBcsdf& bcsdf, const glm::dvec3& wo, double h,
                                    const QuadratureTolerance& tolerance) {
    return integrate_directions([&](const glm::dvec3& wi) { return bcsdf.eval_lobes(wi, wo, h).sum(); },
                                -std::numbers::pi, std::numbers::pi, tolerance);
}

}  // namespace hairlod::bcsdf
