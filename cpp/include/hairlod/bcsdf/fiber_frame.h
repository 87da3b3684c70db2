#pragma once
// Angles of a direction pair in the fibre frame (tangent along +x, sin(theta) = x, as in pbrt) and
// the optics of a dielectric cylinder shared by the single-fibre models.
#include <glm/vec3.hpp>

namespace hairlod::bcsdf {

// theta: angle to the normal plane in [-pi/2, pi/2]; phi = atan2(z, y).
struct FiberDirection {
    double sin_theta = 0.0;
    double cos_theta = 1.0;
    double theta = 0.0;
    double phi = 0.0;
};

// Normalises `w` (a zero vector is read as the normal-plane direction +y).
FiberDirection fiber_direction(const glm::dvec3& w);

// Marschner's angles for a pair (Xu et al. 2011, Table 1 and Eq. 6): theta_h = (theta_i + theta_o) / 2,
// theta_d = (theta_o - theta_i) / 2, phi = phi_o - phi_i wrapped to [-pi, pi], phi_h = (phi_i + phi_o) / 2.
struct HalfAngles {
    double theta_h = 0.0;
    double theta_d = 0.0;
    double phi = 0.0;
    double phi_h = 0.0;
};
HalfAngles half_angles(const FiberDirection& wi, const FiberDirection& wo);

// Wraps an angle to [-pi, pi].
double wrap_angle(double angle);

// Unpolarised Fresnel reflectance of a dielectric (eta > 1) seen from outside at cos_incidence.
double fresnel_dielectric(double cos_incidence, double eta);

// Bravais index for the projection onto the normal plane (Marschner et al. 2003; Xu et al. 2011,
// Table 1): eta' = sqrt(eta^2 - sin^2 theta) / cos theta.
double bravais_index(double eta, double sin_theta, double cos_theta);

// Smallest cosine the models divide by (1/cos theta_i, 1/cos^2 theta_d), so that values at exact
// grazing directions stay finite; S cos(theta_i) is unaffected away from theta = +-pi/2.
inline constexpr double kMinCos = 1e-6;

}  // namespace hairlod::bcsdf
