#include "hairlod/lod/kmeans.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

std::vector<float> random_rows(size_t n, size_t dim, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    std::vector<float> values(n * dim);
    // A few blobs, so k-means has structure to find.
    for (size_t i = 0; i < n; ++i)
        for (size_t d = 0; d < dim; ++d) values[i * dim + d] = normal(rng) + 5.0f * static_cast<float>((i * 7 + d) % 5);
    return values;
}

// Plain Lloyd: full assignment in double, means in row order, empty clusters keep their centre.
KMeansResult naive_lloyd(const FeatureRows& rows, std::vector<float> centres, int iterations, double stop_fraction = 0.0) {
    const size_t n = rows.size(), dim = rows.dim, k = centres.size() / dim;
    KMeansResult result;
    result.assignment.resize(n);
    auto assign = [&] {
        size_t changed = 0;
        for (size_t i = 0; i < n; ++i) {
            double best = std::numeric_limits<double>::infinity();
            int32_t index = 0;
            for (size_t c = 0; c < k; ++c) {
                double d2 = 0.0;
                for (size_t d = 0; d < dim; ++d) {
                    const double e = static_cast<double>(rows.row(i)[d]) - centres[c * dim + d];
                    d2 += e * e;
                }
                if (d2 < best) {
                    best = d2;
                    index = static_cast<int32_t>(c);
                }
            }
            changed += index != result.assignment[i] ? 1 : 0;
            result.assignment[i] = index;
        }
        return changed;
    };
    assign();
    for (int it = 0; it < iterations; ++it) {
        for (size_t c = 0; c < k; ++c) {
            std::vector<double> sum(dim, 0.0);
            size_t count = 0;
            for (size_t i = 0; i < n; ++i)
                if (result.assignment[i] == static_cast<int32_t>(c)) {
                    ++count;
                    for (size_t d = 0; d < dim; ++d) sum[d] += rows.row(i)[d];
                }
            if (count > 0)
                for (size_t d = 0; d < dim; ++d) centres[c * dim + d] = static_cast<float>(sum[d] / static_cast<double>(count));
        }
        ++result.iterations;
        const size_t changed = assign();
        result.converged = changed == 0;
        if (static_cast<double>(changed) <= stop_fraction * static_cast<double>(n)) break;
    }
    result.centres = centres;
    return result;
}

TEST(KMeans, EqualsNaiveLloydFromTheSameSeeds) {
    const std::vector<float> values = random_rows(600, 12, 3);
    const FeatureRows rows{values, 12};
    const std::vector<float> seeds = kmeans_plus_plus_seeds(rows, 9, 11);
    ASSERT_EQ(seeds.size(), 9u * 12u);
    const KMeansResult fast = kmeans(rows, seeds, 50);
    const KMeansResult naive = naive_lloyd(rows, seeds, 50);
    EXPECT_EQ(fast.assignment, naive.assignment);
    EXPECT_EQ(fast.iterations, naive.iterations);
    EXPECT_EQ(fast.converged, naive.converged);
    ASSERT_EQ(fast.centres.size(), naive.centres.size());
    for (size_t i = 0; i < fast.centres.size(); ++i) EXPECT_NEAR(fast.centres[i], naive.centres[i], 1e-5f);
}

TEST(KMeans, StopFractionEqualsNaiveLloydWithTheSameRule) {
    const std::vector<float> values = random_rows(2000, 12, 4);
    const FeatureRows rows{values, 12};
    const std::vector<float> seeds = kmeans_plus_plus_seeds(rows, 24, 5);
    const KMeansResult fast = kmeans(rows, seeds, 50, 0.01);
    const KMeansResult naive = naive_lloyd(rows, seeds, 50, 0.01);
    EXPECT_EQ(fast.assignment, naive.assignment);
    EXPECT_EQ(fast.iterations, naive.iterations);
    EXPECT_EQ(fast.converged, naive.converged);
    EXPECT_THROW(kmeans(rows, seeds, 5, 1.0), Error);
}

// k-means++ without pruning: every row measured against every new centre, same draws.
std::vector<float> naive_seeds(const FeatureRows& rows, size_t k, uint64_t seed) {
    const size_t n = rows.size(), dim = rows.dim;
    std::mt19937_64 rng(seed);
    auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    std::vector<float> centres, nearest(n, std::numeric_limits<float>::infinity());
    size_t chosen = std::min(static_cast<size_t>(uniform() * static_cast<double>(n)), n - 1);
    while (true) {
        centres.insert(centres.end(), rows.row(chosen), rows.row(chosen) + dim);
        if (centres.size() / dim == k) break;
        for (size_t i = 0; i < n; ++i) nearest[i] = std::min(nearest[i], squared_distance(rows.row(i), rows.row(chosen), dim));
        double total = 0.0;
        for (float d : nearest) total += d;
        if (!(total > 0.0)) break;
        const double target = uniform() * total;
        double running = 0.0;
        for (size_t i = 0; i < n; ++i) {
            if (nearest[i] <= 0.0f) continue;
            chosen = i;
            running += nearest[i];
            if (running > target) break;
        }
    }
    return centres;
}

TEST(KMeans, PrunedSeedingEqualsUnprunedSeeding) {
    const std::vector<float> values = random_rows(3000, 12, 6);
    const FeatureRows rows{values, 12};
    for (uint64_t seed : {1u, 2u, 3u}) EXPECT_EQ(kmeans_plus_plus_seeds(rows, 40, seed), naive_seeds(rows, 40, seed));
}

TEST(KMeans, SeedingIsDeterministicAndDistinct) {
    const std::vector<float> values = random_rows(300, 6, 5);
    const FeatureRows rows{values, 6};
    EXPECT_EQ(kmeans_plus_plus_seeds(rows, 20, 7), kmeans_plus_plus_seeds(rows, 20, 7));
    EXPECT_NE(kmeans_plus_plus_seeds(rows, 20, 7), kmeans_plus_plus_seeds(rows, 20, 8));
}

TEST(KMeans, IdenticalRowsGiveOneSeed) {
    const std::vector<float> values(50 * 3, 2.5f);
    const FeatureRows rows{values, 3};
    const std::vector<float> seeds = kmeans_plus_plus_seeds(rows, 8, 0);
    EXPECT_EQ(seeds.size(), 3u);
    const KMeansResult result = kmeans(rows, seeds, 10);
    EXPECT_TRUE(result.converged);
    for (int32_t a : result.assignment) EXPECT_EQ(a, 0);
}

TEST(KMeans, MoreClustersThanRowsAndEmptyClusters) {
    const std::vector<float> values{0, 0, 1, 1, 5, 5};
    const FeatureRows rows{values, 2};
    EXPECT_EQ(kmeans_plus_plus_seeds(rows, 10, 1).size(), 3u * 2u);
    // A centre far from every row stays empty and keeps its position.
    const KMeansResult result = kmeans(rows, {0, 0, 5, 5, 100, 100}, 10);
    EXPECT_EQ(result.assignment, (std::vector<int32_t>{0, 0, 1}));
    EXPECT_FLOAT_EQ(result.centres[4], 100.0f);
    const std::vector<int64_t> medoids = cluster_medoids(rows, group_by_cluster(result.assignment, 3));
    EXPECT_EQ(medoids[2], -1);
}

TEST(KMeans, MedoidsMatchBruteForce) {
    const std::vector<float> values = random_rows(200, 9, 9);
    const FeatureRows rows{values, 9};
    const KMeansResult result = kmeans(rows, kmeans_plus_plus_seeds(rows, 6, 2), 30);
    const ClusterMembers clusters = group_by_cluster(result.assignment, 6);
    const std::vector<int64_t> medoids = cluster_medoids(rows, clusters);
    for (size_t c = 0; c < 6; ++c) {
        double best = std::numeric_limits<double>::infinity();
        int64_t brute = -1;
        for (int64_t i : clusters.of(c)) {
            double total = 0.0;
            for (int64_t j : clusters.of(c)) total += squared_distance(rows.row(static_cast<size_t>(i)), rows.row(static_cast<size_t>(j)), 9);
            if (total < best) {
                best = total;
                brute = i;
            }
        }
        EXPECT_EQ(medoids[c], brute) << "cluster " << c;
    }
}

TEST(KMeans, RejectsBadCentres) {
    const std::vector<float> values{0, 0, 1, 1};
    EXPECT_THROW(kmeans({values, 2}, {}, 5), Error);
    EXPECT_THROW(kmeans({values, 2}, {1, 2, 3}, 5), Error);
}

}  // namespace
}  // namespace hairlod
