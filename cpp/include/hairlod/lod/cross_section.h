#pragma once
// Elliptical cross-section of a thick hair at one control-point index, fitted to where the members
// cross the plane normal to their mean tangent (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 3 fits
// their k-th control points; strand_plane_crossing says why not).
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace hairlod {

struct CrossSection {
    glm::vec3 centre{0.0f};      // mean of the member points
    glm::vec3 tangent{0.0f};     // normalised mean member tangent (zero if they cancel)
    glm::vec3 major_axis{1.0f, 0.0f, 0.0f};  // unit PCA axes that remain after dropping the one
    glm::vec3 minor_axis{0.0f, 1.0f, 0.0f};  // closest to the tangent
    float major_radius = 0.0f;
    float minor_radius = 0.0f;
    int covered = 0;  // members inside the ellipse (projected onto its plane)

    float area() const { return 3.14159265f * major_radius * minor_radius; }
};

// True when `point` projected onto the section's plane lies inside the ellipse.
bool inside_ellipse(const CrossSection& section, const glm::vec3& point);

// Where the polyline `strand` crosses the plane through `centre` with unit `normal`, at the crossing
// nearest (in control points) to its point k; its point k moved along `normal` onto the plane when
// it does not reach the plane. A thick hair's section at control point k is fitted to these points of
// its members in the plane normal to their mean tangent: the points a tube of sections holds. Their
// k-th points themselves lie on a plane tilted from the strands wherever the strands differ in length
// or spread, and an ellipse in that plane (Sec. 5.1 step 3 as written) misses many of the strands.
glm::vec3 strand_plane_crossing(std::span<const glm::vec3> strand, size_t k, const glm::vec3& centre, const glm::vec3& normal);

// The smallest factor >= 1 (times a tiny margin against rounding) by which the section's radii
// must grow so that at least `count` (>= 1) of `points` lie inside. `scratch` is reused.
double growth_to_cover(const CrossSection& section, std::span<const glm::vec3> points, size_t count,
                       std::vector<float>& scratch);

// Fits the ellipse to `points` (with unit `tangents`, one per point, and the strands' radius):
// PCA of the points about their mean, the axis closest to the tangent dropped, and radii
// s * sqrt(variance + radius^2) with s >= 1 the smallest scale putting at least a fraction
// `coverage` of the points inside. `scratch` is reused between calls.
CrossSection fit_cross_section(std::span<const glm::vec3> points, std::span<const glm::vec3> tangents,
                               float strand_radius, float coverage, std::vector<float>& scratch);

// Largest distance between the 4 corners (centre +- semi-axes) projected onto the plane normal to
// the unit `tangent` (Sec. 5.2 "Hair width calculation", in world units). The projected corners are
// +-a and +-b (a, b the projected semi-axes): |a +- b| <= |a| + |b| <= 2 max(|a|, |b|), so the
// largest of the six distances is 2 max(|a|, |b|).
// Inline: skinning evaluates it per level, cluster and control point every frame.
inline float section_diameter(const glm::vec3& tangent, const glm::vec3& major, const glm::vec3& minor) {
    const glm::vec3 a = major - glm::dot(major, tangent) * tangent, b = minor - glm::dot(minor, tangent) * tangent;
    return 2.0f * std::sqrt(std::max(glm::dot(a, a), glm::dot(b, b)));
}

}  // namespace hairlod
