#include "hairlod/lod/quadratic_stencil.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/core/vector_clones.h"
#include "hairlod/lod/compact.h"
#include "hairlod/lod/lod_asset.h"

namespace hairlod {

namespace {

constexpr int kMonomials = kFieldMonomials;
constexpr int kPointsPerGuide = 3;  // control points k - 1, k, k + 1
// The ridge towards the prism map, as a fraction of the fit's mean diagonal: directions the guides
// determine this weakly (or not at all) follow the prism map instead of amplifying the field's
// higher-order terms.
constexpr double kRidge = 1e-6;

using Monomials = std::array<double, kMonomials>;

Monomials monomials(const glm::dvec3& x) {
    return {1.0, x.x, x.y, x.z, x.x * x.x, x.y * x.y, x.z * x.z, x.x * x.y, x.y * x.z, x.z * x.x};
}

// Solves m x = b in place for a symmetric positive definite n x n m (row-major, lower triangle
// read) and `columns` right-hand sides b [n x columns] (Cholesky). The matrix here is SPD by
// construction (the ridge), so a non-positive pivot only comes from rounding: it is clamped to a
// tiny fraction of the diagonal rather than failing.
template <int N>
void solve_spd(std::array<double, N * N> m, double* b, int columns) {
    double largest = 0.0;
    for (int i = 0; i < N; ++i) largest = std::max(largest, m[i * N + i]);
    for (int j = 0; j < N; ++j) {
        double diagonal = m[j * N + j];
        for (int p = 0; p < j; ++p) diagonal -= m[j * N + p] * m[j * N + p];
        diagonal = std::sqrt(std::max(diagonal, 1e-300 + 1e-15 * largest));
        m[j * N + j] = diagonal;
        for (int i = j + 1; i < N; ++i) {
            double sum = m[i * N + j];
            for (int p = 0; p < j; ++p) sum -= m[i * N + p] * m[j * N + p];
            m[i * N + j] = sum / diagonal;
        }
    }
    for (int c = 0; c < columns; ++c) {
        for (int i = 0; i < N; ++i) {  // L y = b
            double sum = b[i * columns + c];
            for (int p = 0; p < i; ++p) sum -= m[i * N + p] * b[p * columns + c];
            b[i * columns + c] = sum / m[i * N + i];
        }
        for (int i = N - 1; i >= 0; --i) {  // L^T x = y
            double sum = b[i * columns + c];
            for (int p = i + 1; p < N; ++p) sum -= m[p * N + i] * b[p * columns + c];
            b[i * columns + c] = sum / m[i * N + i];
        }
    }
}

// The guide terms of one stencil, coordinate by coordinate over the monomials: the loop the frame's
// time goes to (16528 stencils of 24 terms for 100k strands), in AVX2 where the CPU has it.
HAIRLOD_VECTOR_CLONES void guide_term_sums(const StencilTerm* __restrict terms, int count,
                                           const glm::vec3* __restrict deformed_guides, glm::vec3 reference,
                                           float* __restrict sum_x, float* __restrict sum_y, float* __restrict sum_z) {
    for (int j = 0; j < count; ++j) {
        const glm::vec3 v = deformed_guides[static_cast<size_t>(terms[j].point)] - reference;
        const std::array<float, kMonomials>& w = terms[j].weight;
        for (size_t m = 0; m < kMonomials; ++m) {
            sum_x[m] += w[m] * v.x;
            sum_y[m] += w[m] * v.y;
            sum_z[m] += w[m] * v.z;
        }
    }
}

}  // namespace

SkinningStencils skinning_stencils(const LodAsset& asset, std::span<const GuideFrame> rest_frames) {
    const auto nc = static_cast<size_t>(asset.control_points);
    const size_t clusters = asset.cluster_count(), guides = asset.guide_count();
    const int nearest = static_cast<int>(std::min<size_t>(kStencilGuides, guides));
    const size_t stride = static_cast<size_t>(nearest) * kPointsPerGuide;
    SkinningStencils out;
    out.stencils.resize(clusters * nc);
    out.terms.resize(clusters * nc * stride);
    tbb::parallel_for(size_t{0}, clusters, [&](size_t c) {
        const auto [first, end] = asset.cluster_strands(c);
        const auto members = static_cast<double>(end - first);
        std::vector<std::pair<double, int32_t>> by_distance(guides);
        for (size_t k = 0; k < nc; ++k) {
            const size_t i = c * nc + k;
            const GuideFrame& frame = rest_frames[i];
            const QuantisationBox& box = asset.offset_boxes[i];
            auto rest_point = [&](int32_t position) {
                return glm::dvec3(frame.origin) + glm::dvec3(box.decode(asset.strand_offset[static_cast<size_t>(position) * nc + k]));
            };
            glm::dvec3 centroid(0.0);
            for (int32_t s = first; s < end; ++s) centroid += rest_point(s);
            centroid /= members;

            // The nearest guides at k, and the field's length scale h: the farthest of them, or
            // the guides' segment length when they crowd closer (so k +- 1 keep their weight).
            for (size_t g = 0; g < guides; ++g)
                by_distance[g] = {glm::distance(glm::dvec3(asset.rest_guides[g * nc + k]), centroid), static_cast<int32_t>(g)};
            std::partial_sort(by_distance.begin(), by_distance.begin() + nearest, by_distance.end());
            const size_t before = k == 0 ? 0 : k - 1, after = std::min(k + 1, nc - 1);
            double segment = 0.0;
            for (int n = 0; n < nearest; ++n) {
                const size_t g = static_cast<size_t>(by_distance[static_cast<size_t>(n)].second);
                segment += glm::distance(glm::dvec3(asset.rest_guides[g * nc + after]), glm::dvec3(asset.rest_guides[g * nc + before])) /
                           static_cast<double>(std::max<size_t>(after - before, 1));
            }
            double h = std::max(by_distance[static_cast<size_t>(nearest) - 1].first, segment / nearest);
            if (!(h > 0.0)) h = 1.0;  // every point coincides: only the constant is fitted, the prism map decides the rest

            // The weighted normal equations N of the quadratic field, with the ridge.
            StencilTerm* terms = out.terms.data() + i * stride;
            std::array<double, kStencilGuides * kPointsPerGuide> weight{};
            std::array<Monomials, kStencilGuides * kPointsPerGuide> basis{};
            std::array<double, kMonomials * kMonomials> normal{};
            int count = 0;
            for (int n = 0; n < nearest; ++n) {
                const size_t g = static_cast<size_t>(by_distance[static_cast<size_t>(n)].second);
                for (size_t kk = before; kk <= after; ++kk) {
                    const glm::dvec3 x = (glm::dvec3(asset.rest_guides[g * nc + kk]) - centroid) / h;
                    weight[static_cast<size_t>(count)] = std::exp(-glm::dot(x, x));
                    basis[static_cast<size_t>(count)] = monomials(x);
                    terms[count].point = static_cast<int32_t>(g * nc + kk);
                    for (int r = 0; r < kMonomials; ++r)
                        for (int col = 0; col < kMonomials; ++col)
                            normal[static_cast<size_t>(r * kMonomials + col)] +=
                                weight[static_cast<size_t>(count)] * basis[static_cast<size_t>(count)][static_cast<size_t>(r)] *
                                basis[static_cast<size_t>(count)][static_cast<size_t>(col)];
                    ++count;
                }
            }
            double trace = 0.0;
            for (int r = 0; r < kMonomials; ++r) trace += normal[static_cast<size_t>(r * kMonomials + r)];
            const double ridge = kRidge * trace / kMonomials;
            for (int r = 0; r < kMonomials; ++r) normal[static_cast<size_t>(r * kMonomials + r)] += ridge;

            // The field's coefficients are N^-1 (sum_j w_j b_j d_j^T + ridge prior): each term's
            // weights are w_j N^-1 b_j, the prior's the ridge times N^-1's columns 0 to 3.
            std::array<double, kMonomials * kMonomials> inverse{};
            for (int r = 0; r < kMonomials; ++r) inverse[static_cast<size_t>(r * kMonomials + r)] = 1.0;
            solve_spd<kMonomials>(normal, inverse.data(), kMonomials);
            for (int j = 0; j < count; ++j)
                for (int r = 0; r < kMonomials; ++r) {
                    double sum = 0.0;
                    for (int col = 0; col < kMonomials; ++col)
                        sum += inverse[static_cast<size_t>(r * kMonomials + col)] * basis[static_cast<size_t>(j)][static_cast<size_t>(col)];
                    terms[j].weight[static_cast<size_t>(r)] = static_cast<float>(weight[static_cast<size_t>(j)] * sum);
                }
            QuadraticStencil& stencil = out.stencils[i];
            stencil.centroid = centroid;
            stencil.scale = h;
            stencil.reference = static_cast<int32_t>(static_cast<size_t>(by_distance[0].second) * nc + k);
            stencil.first_term = static_cast<int32_t>(i * stride);
            stencil.term_count = count;
            // The prism map's coefficients in the scaled monomials: constant c0, linear h M e_i.
            for (int prior = 0; prior < 4; ++prior)
                for (int r = 0; r < kMonomials; ++r)
                    stencil.prior[prior][static_cast<size_t>(r)] =
                        static_cast<float>(ridge * (prior == 0 ? 1.0 : h) * inverse[static_cast<size_t>(r * kMonomials + prior)]);
        }
    });
    return out;
}

QuadraticMap stencil_map(const SkinningStencils& stencils, size_t i, std::span<const glm::vec3> deformed_guides,
                         const GuideFrame& rest_frame, const GuideFrame& deformed_frame, const glm::mat3& prism_map,
                         const glm::dvec3& anchor) {
    const QuadraticStencil& stencil = stencils.stencils[i];
    std::array<float, kMonomials> sum_x{}, sum_y{}, sum_z{};
    const glm::vec3 reference_f = deformed_guides[static_cast<size_t>(stencil.reference)];
    const glm::dvec3 reference(reference_f);
    guide_term_sums(stencils.terms.data() + stencil.first_term, stencil.term_count, deformed_guides.data(), reference_f,
                    sum_x.data(), sum_y.data(), sum_z.data());
    // The prism map's share, in the same float sums: c0 prior[0]_m + sum_i (M e_i) prior[1 + i]_m.
    const glm::dmat3 prism(prism_map);
    const glm::vec3 c0(glm::dvec3(deformed_frame.origin) - reference + prism * (stencil.centroid - glm::dvec3(rest_frame.origin)));
    for (size_t m = 0; m < kMonomials; ++m) {
        const float p0 = stencil.prior[0][m], p1 = stencil.prior[1][m], p2 = stencil.prior[2][m], p3 = stencil.prior[3][m];
        sum_x[m] += c0.x * p0 + prism_map[0].x * p1 + prism_map[1].x * p2 + prism_map[2].x * p3;
        sum_y[m] += c0.y * p0 + prism_map[0].y * p1 + prism_map[1].y * p2 + prism_map[2].y * p3;
        sum_z[m] += c0.z * p0 + prism_map[0].z * p1 + prism_map[1].z * p2 + prism_map[2].z * p3;
    }
    std::array<glm::dvec3, kMonomials> field{};  // C_m
    for (size_t m = 0; m < kMonomials; ++m) field[m] = glm::dvec3(sum_x[m], sum_y[m], sum_z[m]);

    // The field is quadratic, so its Taylor expansion at the anchor is exact: the value, the
    // gradient (over the scale, as x = (p - centroid) / scale) and the second-order coefficients.
    const double h = stencil.scale;
    const glm::dvec3 x = (anchor - stencil.centroid) / h;
    const Monomials b = monomials(x);
    QuadraticMap map;
    map.origin = reference;
    for (int m = 0; m < kMonomials; ++m) map.origin += b[static_cast<size_t>(m)] * field[static_cast<size_t>(m)];
    // d/dx_a of x_a^2 is 2 x_a; of the products xy, yz, zx the other factor.
    map.linear[0] = (field[1] + 2.0 * x.x * field[4] + x.y * field[7] + x.z * field[9]) / h;
    map.linear[1] = (field[2] + 2.0 * x.y * field[5] + x.x * field[7] + x.z * field[8]) / h;
    map.linear[2] = (field[3] + 2.0 * x.z * field[6] + x.y * field[8] + x.x * field[9]) / h;
    for (int m = 0; m < 6; ++m) map.quadratic[static_cast<size_t>(m)] = field[static_cast<size_t>(4 + m)] / (h * h);
    return map;
}

}  // namespace hairlod
