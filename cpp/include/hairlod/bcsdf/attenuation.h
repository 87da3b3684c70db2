#pragma once
// Attenuation of the light paths through a smooth dielectric cylinder: Fresnel factors and
// absorption along the internal chords, shared by the Chiang, Marschner and R/TT/D models.
#include <array>

#include <glm/vec3.hpp>

namespace hairlod::bcsdf {

struct FiberAttenuation {
    // A_0 = f (R), A_1 = (1 - f)^2 T (TT), A_2 = (1 - f)^2 f T^2 (TRT), A_3 = the sum over p >= 3 (TRRT+).
    std::array<glm::dvec3, 4> a{};
    double gamma_o = 0.0;  // asin(h)
    double gamma_t = 0.0;  // asin(h / eta')
};

// Xu et al. 2011, Eq. 10 and Table 1 (Chiang et al. 2016, Sec. 4.3, adds the residual A_3): at inclination theta (sin, cos) and
// offset h, f = Fresnel of the 3D incidence cos(theta) cos(gamma_o), T = exp(-sigma_a 2 cos(gamma_t)
// / cos(theta_t)) with sin(theta_t) = sin(theta) / eta and sin(gamma_t) = h / eta'.
FiberAttenuation fiber_attenuation(double eta, const glm::dvec3& sigma_a, double sin_theta, double cos_theta,
                                   double h);

// The attenuations averaged over the offset h in [-1, 1] (1/2 the integral over h), by composite
// Gauss-Legendre in asin(h): 1e-4 relative to adaptive quadrature up to theta = 1.5 (tested).
std::array<glm::dvec3, 4> mean_fiber_attenuation(double eta, const glm::dvec3& sigma_a, double sin_theta,
                                                 double cos_theta);

}  // namespace hairlod::bcsdf
