#pragma once
// Exact k-means on fixed-length feature vectors (a strand's control points flattened), used for
// guide selection (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 1) and for splitting clusters into
// finer levels. Results depend only on the data and the seed, never on the thread count.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace hairlod {

// `values` holds rows of `dim` floats, one feature vector per item.
struct FeatureRows {
    std::span<const float> values;
    size_t dim = 1;

    size_t size() const { return values.size() / dim; }
    const float* row(size_t i) const { return values.data() + i * dim; }
};

// D(i, j) = sum_k |p_ik - p_jk|^2 of hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 1 when rows are
// flattened control points.
float squared_distance(const float* a, const float* b, size_t dim);

// k-means++ seeding: the first centre uniformly, each next one with probability proportional to
// the squared distance to the nearest chosen centre. Returns up to k centres (rows of dim floats):
// fewer when the data has fewer than k distinct rows.
std::vector<float> kmeans_plus_plus_seeds(const FeatureRows& rows, size_t k, uint64_t seed);

struct KMeansResult {
    std::vector<float> centres;       // k rows of dim floats; an empty cluster keeps its last centre
    std::vector<int32_t> assignment;  // nearest centre of each row (lowest index on ties)
    int iterations = 0;               // centre updates performed
    bool converged = false;           // the last update changed no assignment
};

// Lloyd's algorithm accelerated with Hamerly's bounds (one upper bound to the assigned centre,
// one lower bound to all others), so it returns the same assignment as plain Lloyd iterations
// from the same centres. Centre sums are accumulated in double in row order. Stops after
// max_iterations centre updates, or after the first update whose reassignment moves at most
// stop_fraction * rows rows (0: only at convergence). The tail of Lloyd's iterations moves a few
// boundary rows between neighbouring clusters, which barely changes the medoids used as guides.
KMeansResult kmeans(const FeatureRows& rows, std::vector<float> initial_centres, int max_iterations,
                    double stop_fraction = 0.0);

// Rows grouped by cluster: cluster c owns members[first[c] .. first[c + 1]), in increasing row order.
struct ClusterMembers {
    std::vector<int64_t> first;
    std::vector<int64_t> members;

    std::span<const int64_t> of(size_t cluster) const {
        return {members.data() + first[cluster], static_cast<size_t>(first[cluster + 1] - first[cluster])};
    }
};
ClusterMembers group_by_cluster(std::span<const int32_t> assignment, size_t clusters);

// The exact medoid of each cluster (the member with the smallest summed squared distance to the
// other members, lowest row on ties), or -1 for an empty cluster. Linear time through
// sum_j |x_i - x_j|^2 = n |x_i - mean|^2 + sum_j |x_j - mean|^2: the medoid is the member
// closest to the mean.
std::vector<int64_t> cluster_medoids(const FeatureRows& rows, const ClusterMembers& clusters);

}  // namespace hairlod
