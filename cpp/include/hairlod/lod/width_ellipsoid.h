#pragma once
// A view-dependent bound of a cluster's thick-hair widths (hair-lod-aggregated-bcsdf.txt Sec. 5.2
// "Hair width calculation"). The paper measures each thick hair's width on screen from its four
// corners projected onto the plane normal to its tangent: 2 max(|B a|, |B b|) / w for semi-axes a,
// b in that plane, B the camera's pixel-scaled xy rows and w the centre's clip w (projected_width).
// That width depends on the view: a flat thick hair seen edge-on is as wide as it is thick. The
// selection keeps per L0 cluster, level and control point one ellipsoid {x : x^T E^-1 x <= 1} that
// holds the semi-axes of every hair of the cluster there; for any camera
//   max over those semi-axes of |B x| = sqrt(lambda_max(B E B^T)),
// the largest eigenvalue of a 2 x 2 matrix: a few flops per point and view, never below the
// paper's width of any hair of the cluster, and close to it whatever the direction of view.
#include <array>
#include <span>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace hairlod {

// E = sum_i axes[i] axes[i]^T. Under a map with Jacobian J the semi-axes move to J x, and the
// ellipsoid holding them to the axes J axes[i].
struct WidthEllipsoid {
    std::array<glm::vec3, 3> axes{};
};

// E as stored for selection: (xx, yy, zz, xy, yz, zx).
using SymmetricEntries = std::array<float, 6>;

// The ellipsoid of a cluster at one control point, shaped on its widest hair (semi-axes `major`
// and `minor`, normal to `tangent`) and grown until it holds every vector of `semi_axes` (each hair's
// two semi-axes projected onto the plane normal to its own tangent). Its third axis, along the
// tangent, and its minor axis are at least 1/8 of the major one, so a sibling hair turned a little
// out of the widest hair's plane grows it only a little.
WidthEllipsoid width_ellipsoid(const glm::vec3& tangent, const glm::vec3& major, const glm::vec3& minor,
                               std::span<const glm::vec3> semi_axes);

WidthEllipsoid mapped(const WidthEllipsoid& ellipsoid, const glm::mat3& jacobian);

// The smallest diameter of an ellipsoid width_ellipsoid made (its axes orthogonal), a hair's
// breadth less against rounding: no camera sees its projection narrower than this diameter at the
// camera's largest stretch, so a point this says is too wide needs no 2 x 2 eigenvalue.
float thinnest_diameter(const WidthEllipsoid& ellipsoid);

SymmetricEntries symmetric_entries(const WidthEllipsoid& ellipsoid);

}  // namespace hairlod
