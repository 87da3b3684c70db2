#include "hairlod/lod/kmeans.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "hairlod/core/error.h"

namespace hairlod {

namespace {

// Bounds are compared with this relative slack so that float rounding in the distances never
// lets Hamerly's test skip a row whose nearest centre Lloyd would change.
constexpr float kBoundSlack = 1.0f + 1e-5f;
// Relative slack on squared distances for the triangle-inequality pruning of the seeding: far
// above the rounding of a float squared distance (about dim * 2^-24).
constexpr float kPruneSlack = 1.0f + 1e-3f;

double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

struct Nearest {
    int32_t index = 0;
    float first = std::numeric_limits<float>::infinity();   // squared distance to the nearest centre
    float second = std::numeric_limits<float>::infinity();  // squared distance to the next nearest
};

Nearest nearest_two(const float* x, const std::vector<float>& centres, size_t dim) {
    Nearest result;
    const size_t k = centres.size() / dim;
    for (size_t j = 0; j < k; ++j) {
        const float d = squared_distance(x, centres.data() + j * dim, dim);
        if (d < result.first) {
            result.second = result.first;
            result.first = d;
            result.index = static_cast<int32_t>(j);
        } else if (d < result.second) {
            result.second = d;
        }
    }
    return result;
}

// New centres as member means, summed in double in row order; empty clusters keep their centre.
void update_centres(const FeatureRows& rows, const ClusterMembers& clusters, std::vector<float>& centres) {
    const size_t dim = rows.dim, k = centres.size() / dim;
    tbb::parallel_for(size_t{0}, k, [&](size_t c) {
        const std::span<const int64_t> members = clusters.of(c);
        if (members.empty()) return;
        std::vector<double> sum(dim, 0.0);
        for (int64_t i : members) {
            const float* x = rows.row(static_cast<size_t>(i));
            for (size_t d = 0; d < dim; ++d) sum[d] += x[d];
        }
        for (size_t d = 0; d < dim; ++d)
            centres[c * dim + d] = static_cast<float>(sum[d] / static_cast<double>(members.size()));
    });
}

}  // namespace

float squared_distance(const float* a, const float* b, size_t dim) {
    // Four independent partial sums let the compiler vectorise without reassociating.
    float s0 = 0.0f, s1 = 0.0f, s2 = 0.0f, s3 = 0.0f;
    size_t d = 0;
    for (; d + 4 <= dim; d += 4) {
        const float e0 = a[d] - b[d], e1 = a[d + 1] - b[d + 1], e2 = a[d + 2] - b[d + 2], e3 = a[d + 3] - b[d + 3];
        s0 += e0 * e0;
        s1 += e1 * e1;
        s2 += e2 * e2;
        s3 += e3 * e3;
    }
    for (; d < dim; ++d) {
        const float e = a[d] - b[d];
        s0 += e * e;
    }
    return (s0 + s1) + (s2 + s3);
}

std::vector<float> kmeans_plus_plus_seeds(const FeatureRows& rows, size_t k, uint64_t seed) {
    const size_t n = rows.size(), dim = rows.dim;
    if (n == 0 || k == 0) return {};
    std::mt19937_64 rng(seed);
    std::vector<float> centres;
    centres.reserve(std::min(k, n) * dim);
    size_t chosen = std::min(static_cast<size_t>(uniform01(rng) * static_cast<double>(n)), n - 1);
    std::vector<float> nearest(n, std::numeric_limits<float>::infinity());
    std::vector<int32_t> nearest_centre(n, -1);
    std::vector<float> gap_to_new;  // squared distances from the newest centre to the earlier ones
    while (true) {
        centres.insert(centres.end(), rows.row(chosen), rows.row(chosen) + dim);
        const size_t newest = centres.size() / dim - 1;
        if (newest + 1 == k) break;
        const float* centre = rows.row(chosen);
        gap_to_new.resize(newest);
        for (size_t j = 0; j < newest; ++j) gap_to_new[j] = squared_distance(centre, centres.data() + j * dim, dim);
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& range) {
            for (size_t i = range.begin(); i != range.end(); ++i) {
                // Triangle inequality: |c_new - c_j| >= 2 |x - c_j| means |x - c_new| >= |x - c_j|,
                // so the nearest distance cannot shrink (the slack absorbs float rounding, keeping
                // the seeds identical to the unpruned loop).
                const int32_t j = nearest_centre[i];
                if (j >= 0 && gap_to_new[static_cast<size_t>(j)] >= 4.0f * kPruneSlack * nearest[i]) continue;
                const float d = squared_distance(rows.row(i), centre, dim);
                if (d < nearest[i]) {
                    nearest[i] = d;
                    nearest_centre[i] = static_cast<int32_t>(newest);
                }
            }
        });
        // Sequential sums keep the draw independent of the thread count.
        double total = 0.0;
        for (float d : nearest) total += d;
        if (!(total > 0.0)) break;  // every row coincides with a centre: no more distinct seeds
        const double target = uniform01(rng) * total;
        double running = 0.0;
        chosen = n;
        for (size_t i = 0; i < n; ++i) {
            if (nearest[i] <= 0.0f) continue;
            chosen = i;
            running += nearest[i];
            if (running > target) break;
        }
    }
    return centres;
}

ClusterMembers group_by_cluster(std::span<const int32_t> assignment, size_t clusters) {
    ClusterMembers result;
    result.first.assign(clusters + 1, 0);
    for (int32_t c : assignment) ++result.first[static_cast<size_t>(c) + 1];
    for (size_t c = 0; c < clusters; ++c) result.first[c + 1] += result.first[c];
    result.members.resize(assignment.size());
    std::vector<int64_t> cursor(result.first.begin(), result.first.end() - 1);
    for (size_t i = 0; i < assignment.size(); ++i)
        result.members[static_cast<size_t>(cursor[static_cast<size_t>(assignment[i])]++)] = static_cast<int64_t>(i);
    return result;
}

KMeansResult kmeans(const FeatureRows& rows, std::vector<float> initial_centres, int max_iterations, double stop_fraction) {
    const size_t n = rows.size(), dim = rows.dim;
    if (initial_centres.empty() || initial_centres.size() % dim != 0)
        throw Error("kmeans: centres must be a non-empty multiple of " + std::to_string(dim) + " values");
    if (max_iterations < 0) throw Error("kmeans: max_iterations must be >= 0");
    if (!(stop_fraction >= 0.0 && stop_fraction < 1.0)) throw Error("kmeans: stop_fraction must be in [0, 1)");
    const size_t k = initial_centres.size() / dim;
    KMeansResult result;
    result.centres = std::move(initial_centres);
    result.assignment.resize(n);

    // Hamerly's bounds, as Euclidean (not squared) distances.
    std::vector<float> upper(n), lower(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
            const Nearest best = nearest_two(rows.row(i), result.centres, dim);
            result.assignment[i] = best.index;
            upper[i] = std::sqrt(best.first);
            lower[i] = std::sqrt(best.second);
        }
    });

    std::vector<float> previous(result.centres.size()), moved(k), half_gap(k);
    while (result.iterations < max_iterations) {
        previous = result.centres;
        update_centres(rows, group_by_cluster(result.assignment, k), result.centres);
        ++result.iterations;

        // How far each centre moved, the largest two moves, and half the distance from each
        // centre to its nearest other centre.
        size_t largest = 0;
        for (size_t c = 0; c < k; ++c) {
            moved[c] = std::sqrt(squared_distance(previous.data() + c * dim, result.centres.data() + c * dim, dim));
            if (moved[c] > moved[largest]) largest = c;
        }
        float second_largest = 0.0f;
        for (size_t c = 0; c < k; ++c)
            if (c != largest) second_largest = std::max(second_largest, moved[c]);
        tbb::parallel_for(size_t{0}, k, [&](size_t c) {
            float gap = std::numeric_limits<float>::infinity();
            for (size_t j = 0; j < k; ++j)
                if (j != c)
                    gap = std::min(gap, squared_distance(result.centres.data() + c * dim, result.centres.data() + j * dim, dim));
            half_gap[c] = 0.5f * std::sqrt(gap);
        });

        const size_t changed = tbb::parallel_reduce(
            tbb::blocked_range<size_t>(0, n), size_t{0},
            [&](const tbb::blocked_range<size_t>& range, size_t count) {
                for (size_t i = range.begin(); i != range.end(); ++i) {
                    const auto a = static_cast<size_t>(result.assignment[i]);
                    upper[i] += moved[a];
                    lower[i] -= a == largest ? second_largest : moved[largest];
                    float bound = std::max(half_gap[a], lower[i]);
                    if (upper[i] * kBoundSlack <= bound) continue;
                    upper[i] = std::sqrt(squared_distance(rows.row(i), result.centres.data() + a * dim, dim));
                    if (upper[i] * kBoundSlack <= bound) continue;
                    const Nearest best = nearest_two(rows.row(i), result.centres, dim);
                    upper[i] = std::sqrt(best.first);
                    lower[i] = std::sqrt(best.second);
                    if (best.index != result.assignment[i]) {
                        result.assignment[i] = best.index;
                        ++count;
                    }
                }
                return count;
            },
            [](size_t a, size_t b) { return a + b; });
        result.converged = changed == 0;
        if (static_cast<double>(changed) <= stop_fraction * static_cast<double>(n)) break;
    }
    return result;
}

std::vector<int64_t> cluster_medoids(const FeatureRows& rows, const ClusterMembers& clusters) {
    const size_t dim = rows.dim, k = clusters.first.size() - 1;
    std::vector<int64_t> medoid(k, -1);
    tbb::parallel_for(size_t{0}, k, [&](size_t c) {
        const std::span<const int64_t> members = clusters.of(c);
        if (members.empty()) return;
        std::vector<double> mean(dim, 0.0);
        for (int64_t i : members)
            for (size_t d = 0; d < dim; ++d) mean[d] += rows.row(static_cast<size_t>(i))[d];
        for (double& m : mean) m /= static_cast<double>(members.size());
        double best = std::numeric_limits<double>::infinity();
        for (int64_t i : members) {
            const float* x = rows.row(static_cast<size_t>(i));
            double distance = 0.0;
            for (size_t d = 0; d < dim; ++d) distance += (x[d] - mean[d]) * (x[d] - mean[d]);
            if (distance < best) {
                best = distance;
                medoid[c] = i;
            }
        }
    });
    return medoid;
}

}  // namespace hairlod
