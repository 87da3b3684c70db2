#include "hairlod/lod/symmetric_eigen.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

namespace hairlod {

SymmetricEigen3 symmetric_eigen(const glm::dmat3& matrix) {
    // a[row][col] with a symmetric copy of the upper triangle; glm is column-major.
    double a[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = r; c < 3; ++c) a[r][c] = a[c][r] = matrix[c][r];
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

    double scale = 0.0;
    for (auto& row : a)
        for (double x : row) scale = std::max(scale, std::abs(x));
    // Sweeps stop once the off-diagonal part is negligible next to the largest entry; Jacobi
    // converges quadratically, 50 sweeps is a bound never reached in practice.
    for (int sweep = 0; sweep < 50 && scale > 0.0; ++sweep) {
        const double off = std::abs(a[0][1]) + std::abs(a[0][2]) + std::abs(a[1][2]);
        if (off <= 1e-15 * scale) break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                // Rotation angle that zeroes a[p][q] (Golub & Van Loan, Alg. 8.4.1).
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = std::copysign(1.0, theta) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }

    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int i, int j) { return a[i][i] < a[j][j]; });
    SymmetricEigen3 result;
    for (int i = 0; i < 3; ++i) {
        result.values[i] = a[order[i]][order[i]];
        result.vectors[i] = glm::normalize(glm::dvec3(v[0][order[i]], v[1][order[i]], v[2][order[i]]));
    }
    result.vectors[2] = glm::cross(result.vectors[0], result.vectors[1]);
    return result;
}

}  // namespace hairlod
