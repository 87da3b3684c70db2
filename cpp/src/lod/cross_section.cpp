#include "hairlod/lod/cross_section.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairlod/lod/symmetric_eigen.h"

namespace hairlod {

namespace {

// Radii are inflated by this factor so members on the quantile boundary count as inside
// despite rounding.
constexpr double kBoundaryInflation = 1.0 + 1e-5;

// Squared elliptical distance of `point` projected onto the section's plane (1 on the ellipse).
double ellipse_distance_squared(const CrossSection& s, const glm::vec3& point) {
    const glm::dvec3 d = glm::dvec3(point) - glm::dvec3(s.centre);
    const double u = glm::dot(d, glm::dvec3(s.major_axis)), v = glm::dot(d, glm::dvec3(s.minor_axis));
    const double a = s.major_radius, b = s.minor_radius;
    if (a <= 0.0 || b <= 0.0) return u == 0.0 && v == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
    return (u / a) * (u / a) + (v / b) * (v / b);
}

}  // namespace

bool inside_ellipse(const CrossSection& s, const glm::vec3& point) { return ellipse_distance_squared(s, point) <= 1.0; }

glm::vec3 strand_plane_crossing(std::span<const glm::vec3> strand, size_t k, const glm::vec3& centre, const glm::vec3& normal) {
    if (k >= strand.size()) throw Error("strand_plane_crossing: control point " + std::to_string(k) + " past the strand's end");
    const glm::dvec3 c(centre), n(normal);
    auto depth = [&](size_t j) { return glm::dot(glm::dvec3(strand[j]) - c, n); };
    glm::dvec3 crossing = glm::dvec3(strand[k]) - depth(k) * n;
    double nearest = std::numeric_limits<double>::infinity();
    // Segment j spans control points [j, j + 1]: a crossing on it lies at least max(0, j - k, k - j - 1)
    // from k. Segments are visited in rings of that bound (k - 1 and k, then k - 2 and k + 1, ...), and
    // the search stops once a ring cannot beat the crossing found: near k, where strands usually cross,
    // it reads a few points instead of the whole strand.
    auto try_segment = [&](size_t j) {
        const double d0 = depth(j), d1 = depth(j + 1);
        if (d0 * d1 > 0.0 || d0 == d1) return;
        const double f = d0 / (d0 - d1);
        const double distance = std::abs(static_cast<double>(j) + f - static_cast<double>(k));
        if (distance < nearest) {
            nearest = distance;
            crossing = glm::dvec3(strand[j]) + f * (glm::dvec3(strand[j + 1]) - glm::dvec3(strand[j]));
        }
    };
    const size_t segments = strand.size() - 1;
    for (size_t ring = 0; static_cast<double>(ring) < nearest && (ring < k || k + ring < segments); ++ring) {
        if (ring < k) try_segment(k - 1 - ring);
        if (k + ring < segments) try_segment(k + ring);
    }
    return glm::vec3(crossing);
}

double growth_to_cover(const CrossSection& section, std::span<const glm::vec3> points, size_t count,
                       std::vector<float>& scratch) {
    scratch.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) scratch[i] = static_cast<float>(ellipse_distance_squared(section, points[i]));
    const auto nth = scratch.begin() + static_cast<std::ptrdiff_t>(std::clamp<size_t>(count, 1, points.size()) - 1);
    std::nth_element(scratch.begin(), nth, scratch.end());
    return std::max(1.0, std::sqrt(static_cast<double>(*nth))) * kBoundaryInflation;
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

    CrossSection section;
    section.centre = glm::vec3(centre);
    section.tangent = glm::vec3(tangent);
    section.major_axis = glm::vec3(axis_major);
    section.minor_axis = glm::vec3(axis_minor);
    section.major_radius = static_cast<float>(sigma_major);
    section.minor_radius = static_cast<float>(sigma_minor);
    // The smallest scale of the sigma ellipse that covers the requested fraction of points: the
    // matching quantile of their Mahalanobis distances in the ellipse plane.
    const size_t needed = static_cast<size_t>(std::ceil(coverage * count));
    const double scale = growth_to_cover(section, points, needed, scratch);
    section.major_radius = static_cast<float>(scale * sigma_major);
    section.minor_radius = static_cast<float>(scale * sigma_minor);
    for (const glm::vec3& p : points) section.covered += inside_ellipse(section, p) ? 1 : 0;
    return section;
}

}  // namespace hairlod
