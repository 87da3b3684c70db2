#include "hairlod/lod/symmetric_eigen.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace hairlod {
namespace {

// A = V diag(values) V^T must be reproduced to 1e-12 relative and V orthonormal.
void expect_decomposes(const glm::dmat3& a) {
    const SymmetricEigen3 e = symmetric_eigen(a);
    const glm::dmat3 rebuilt = e.vectors * glm::dmat3(e.values.x, 0, 0, 0, e.values.y, 0, 0, 0, e.values.z) *
                               glm::transpose(e.vectors);
    double scale = 1e-300;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) scale = std::max(scale, std::abs(a[c][r]));
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) EXPECT_NEAR(rebuilt[c][r], a[c][r], 1e-12 * scale);
    const glm::dmat3 identity = glm::transpose(e.vectors) * e.vectors;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) EXPECT_NEAR(identity[c][r], c == r ? 1.0 : 0.0, 1e-12);
    EXPECT_LE(e.values.x, e.values.y);
    EXPECT_LE(e.values.y, e.values.z);
}

TEST(SymmetricEigen, GeneralMatrix) { expect_decomposes(glm::dmat3(4, 1, -2, 1, 3, 0.5, -2, 0.5, 1)); }

TEST(SymmetricEigen, ZeroMatrixOfCoincidentPoints) {
    const SymmetricEigen3 e = symmetric_eigen(glm::dmat3(0.0));
    EXPECT_EQ(e.values, glm::dvec3(0.0));
    EXPECT_NEAR(glm::determinant(e.vectors), 1.0, 1e-12);
}

TEST(SymmetricEigen, RankOneMatrixOfCollinearPoints) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(1, 2, 3));
    const glm::dmat3 a = 7.0 * glm::outerProduct(d, d);
    expect_decomposes(a);
    const SymmetricEigen3 e = symmetric_eigen(a);
    EXPECT_NEAR(e.values.z, 7.0, 1e-12);
    EXPECT_NEAR(std::abs(glm::dot(e.vectors[2], d)), 1.0, 1e-12);
    EXPECT_NEAR(e.values.x, 0.0, 1e-12);
}

TEST(SymmetricEigen, RepeatedEigenvaluesAndTinyScale) {
    expect_decomposes(glm::dmat3(2, 0, 0, 0, 2, 0, 0, 0, 5));
    expect_decomposes(1e-30 * glm::dmat3(4, 1, -2, 1, 3, 0.5, -2, 0.5, 1));
    expect_decomposes(1e20 * glm::dmat3(1, 1e-9, 0, 1e-9, 1, 0, 0, 0, 1));
}

}  // namespace
}  // namespace hairlod
