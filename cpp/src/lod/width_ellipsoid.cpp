#include "hairlod/lod/width_ellipsoid.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace hairlod {

namespace {

// Smallest minor and tangent semi-axis of the ellipsoid, as a fraction of the major one.
constexpr float kThinnestAxis = 0.125f;
// Grows the ellipsoid a little past the farthest semi-axis, against rounding in the float quadratic forms.
constexpr double kRoundingMargin = 1e-4;

}  // namespace

WidthEllipsoid width_ellipsoid(const glm::vec3& tangent, const glm::vec3& major, const glm::vec3& minor,
                               std::span<const glm::vec3> semi_axes) {
    // An orthonormal frame on the widest hair: u along its major semi-axis (the longer of the two
    // in the plane normal to the tangent), v its minor one, t normal to both.
    glm::dvec3 a(major - glm::dot(major, tangent) * tangent), b(minor - glm::dot(minor, tangent) * tangent);
    if (glm::dot(b, b) > glm::dot(a, a)) std::swap(a, b);
    const double major_radius = glm::length(a);
    if (!(major_radius > 0.0)) return {};  // a hair of no width: nothing to hold
    const glm::dvec3 u = a / major_radius;
    glm::dvec3 v = b - glm::dot(b, u) * u;
    double minor_radius = glm::length(v);
    if (minor_radius > 0.0) {
        v /= minor_radius;
    } else {  // any direction normal to u
        v = std::abs(u.x) < 0.9 ? glm::normalize(glm::cross(u, glm::dvec3(1, 0, 0))) : glm::normalize(glm::cross(u, glm::dvec3(0, 1, 0)));
    }
    const glm::dvec3 t = glm::cross(u, v);
    minor_radius = std::max(minor_radius, kThinnestAxis * major_radius);
    const glm::dvec3 radii(major_radius, minor_radius, minor_radius);
    // x^T E0^-1 x in the frame (u, v, t) is a sum of squared coordinates over squared radii; the
    // ellipsoid grows by the largest such value so that every semi-axis lies inside.
    double growth = 1.0;
    for (const glm::vec3& axis : semi_axes) {
        const glm::dvec3 x(axis);
        const glm::dvec3 in_frame(glm::dot(x, u), glm::dot(x, v), glm::dot(x, t));
        const glm::dvec3 scaled = in_frame / radii;
        growth = std::max(growth, glm::dot(scaled, scaled));
    }
    const double scale = std::sqrt(growth * (1.0 + kRoundingMargin));
    return {{glm::vec3(u * (radii.x * scale)), glm::vec3(v * (radii.y * scale)), glm::vec3(t * (radii.z * scale))}};
}

WidthEllipsoid mapped(const WidthEllipsoid& ellipsoid, const glm::mat3& jacobian) {
    return {{jacobian * ellipsoid.axes[0], jacobian * ellipsoid.axes[1], jacobian * ellipsoid.axes[2]}};
}

float thinnest_diameter(const WidthEllipsoid& ellipsoid) {
    float smallest = glm::length(ellipsoid.axes[0]);
    for (const glm::vec3& axis : ellipsoid.axes) smallest = std::min(smallest, glm::length(axis));
    return 2.0f * smallest * (1.0f - 1e-4f);
}

SymmetricEntries symmetric_entries(const WidthEllipsoid& ellipsoid) {
    SymmetricEntries e{};
    for (const glm::vec3& x : ellipsoid.axes) {
        e[0] += x.x * x.x;
        e[1] += x.y * x.y;
        e[2] += x.z * x.z;
        e[3] += x.x * x.y;
        e[4] += x.y * x.z;
        e[5] += x.z * x.x;
    }
    return e;
}

}  // namespace hairlod
