#pragma once
// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations: slower than the
// closed-form cubic but accurate for the degenerate spreads hair clusters produce (coincident,
// collinear or planar control points, repeated eigenvalues).
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace hairlod {

struct SymmetricEigen3 {
    glm::dvec3 values{0.0};  // ascending
    glm::dmat3 vectors{1.0};  // column i is the unit eigenvector of values[i]; right-handed
};

// `matrix` must be symmetric (only its upper triangle is read).
SymmetricEigen3 symmetric_eigen(const glm::dmat3& matrix);

}  // namespace hairlod
