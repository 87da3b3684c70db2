#include "hairlod/lod/cross_section.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairlod/lod/symmetric_eigen.h"

namespace hairlod {

namespace {

// Radii are inflated by this factor so members on the quantile boundary count as inside
// despite rounding.
constexpr double kBoundaryInflation = 1.0 + 1e-5;

// The members closest to the four axis endpoints, in one pass over the points.
std::array<int, 4> corner_members(std::span<const glm::vec3> points, const CrossSection& s) {
    const glm::vec3 targets[4] = {s.centre + s.major_radius * s.major_axis, s.centre - s.major_radius * s.major_axis,
                                  s.centre + s.minor_radius * s.minor_axis, s.centre - s.minor_radius * s.minor_axis};
    std::array<int, 4> corners{0, 0, 0, 0};
    float best[4] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                     std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()};
    for (size_t i = 0; i < points.size(); ++i)
        for (int c = 0; c < 4; ++c) {
            const glm::vec3 d = points[i] - targets[c];
            const float distance = glm::dot(d, d);
            if (distance < best[c]) {
                best[c] = distance;
                corners[c] = static_cast<int>(i);
            }
        }
    return corners;
}

}  // namespace

bool inside_ellipse(const CrossSection& s, const glm::vec3& point) {
    const glm::dvec3 d = glm::dvec3(point) - glm::dvec3(s.centre);
    const double u = glm::dot(d, glm::dvec3(s.major_axis)), v = glm::dot(d, glm::dvec3(s.minor_axis));
    const double a = s.major_radius, b = s.minor_radius;
    if (a <= 0.0 || b <= 0.0) return u == 0.0 && v == 0.0;
    return (u / a) * (u / a) + (v / b) * (v / b) <= 1.0;
}

CrossSection fit_cross_section(std::span<const glm::vec3> points, std::span<const glm::vec3> tangents,
                               float strand_radius, float coverage, std::vector<float>& scratch) {
    if (points.empty() || points.size() != tangents.size())
        throw Error("fit_cross_section: needs one tangent per point and at least one point");
    const double count = static_cast<double>(points.size());
    glm::dvec3 centre(0.0), tangent(0.0);
    for (size_t i = 0; i < points.size(); ++i) {
        centre += glm::dvec3(points[i]);
        tangent += glm::dvec3(tangents[i]);
    }
    centre /= count;
    glm::dmat3 covariance(0.0);
    for (const glm::vec3& p : points) {
        const glm::dvec3 d = glm::dvec3(p) - centre;
        covariance += glm::outerProduct(d, d);
    }
    covariance /= count;
    const double tangent_length = glm::length(tangent);
    if (tangent_length > 0.0) tangent /= tangent_length;

    // PCA; the axis closest to the tangent is the hair's direction, not its cross-section.
    const SymmetricEigen3 pca = symmetric_eigen(covariance);
    int along = 0;
    for (int i = 1; i < 3; ++i)
        if (std::abs(glm::dot(pca.vectors[i], tangent)) > std::abs(glm::dot(pca.vectors[along], tangent))) along = i;
    int major = along == 2 ? 1 : 2, minor = along == 0 ? 1 : 0;  // eigenvalues ascend

    // Sigma of each kept axis, widened by the strand radius so a lone strand keeps its own width.
    // The floor keeps the Mahalanobis distance finite for zero spread and zero radius.
    const double r2 = static_cast<double>(strand_radius) * strand_radius;
    const double floor = 1e-7 * std::max({glm::length(centre), std::sqrt(std::max(pca.values[2], 0.0)), 1e-30});
    const double sigma_major = std::max(std::sqrt(std::max(pca.values[major], 0.0) + r2), floor);
    const double sigma_minor = std::max(std::sqrt(std::max(pca.values[minor], 0.0) + r2), floor);
    const glm::dvec3 axis_major = pca.vectors[major], axis_minor = pca.vectors[minor];

    // The smallest scale that covers the requested fraction of points: the matching quantile of
    // their Mahalanobis distances in the ellipse plane.
    scratch.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const glm::dvec3 d = glm::dvec3(points[i]) - centre;
        const double u = glm::dot(d, axis_major) / sigma_major, v = glm::dot(d, axis_minor) / sigma_minor;
        scratch[i] = static_cast<float>(std::sqrt(u * u + v * v));
    }
    const size_t needed = std::clamp<size_t>(static_cast<size_t>(std::ceil(coverage * count)), 1, points.size());
    std::nth_element(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(needed - 1), scratch.end());
    const double scale = std::max(1.0, static_cast<double>(scratch[needed - 1])) * kBoundaryInflation;

    CrossSection section;
    section.centre = glm::vec3(centre);
    section.tangent = glm::vec3(tangent);
    section.major_axis = glm::vec3(axis_major);
    section.minor_axis = glm::vec3(axis_minor);
    section.major_radius = static_cast<float>(scale * sigma_major);
    section.minor_radius = static_cast<float>(scale * sigma_minor);
    section.corners = corner_members(points, section);
    for (const glm::vec3& p : points) section.covered += inside_ellipse(section, p) ? 1 : 0;
    return section;
}

}  // namespace hairlod
