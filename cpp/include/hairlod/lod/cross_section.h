#pragma once
// Elliptical cross-section of a thick hair at one control-point index, fitted to the members'
// control points (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 3).
#include <array>
#include <span>
#include <vector>

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

// Largest distance between the 4 corners (centre +- semi-axes) projected onto the plane through
// `centre` normal to the unit `tangent` (Sec. 5.2 "Hair width calculation", in world units).
float corner_diameter(const glm::vec3& centre, const glm::vec3& tangent, const std::array<glm::vec3, 4>& corners);

}  // namespace hairlod
