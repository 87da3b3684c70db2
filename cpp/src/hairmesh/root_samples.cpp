#include "hairlod/hairmesh/root_samples.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "hairlod/core/error.h"
#include "hairlod/hairmesh/hash_random.h"

namespace hairlod {

namespace {

// Yuksel 2015: candidates per output sample, the weight exponent alpha and the weight-limiting
// constants beta and gamma (Sec. 4 and 5 of that paper).
constexpr size_t kCandidatesPerSample = 5;
// (1 - d / (2 r_max))^alpha with alpha = 8, by repeated squaring.
double weight_of(double x) {
    const double x2 = x * x, x4 = x2 * x2;
    return x4 * x4;
}
constexpr double kLimitBeta = 0.65;
constexpr double kLimitGamma = 1.5;

double domain_area(SampleDomain domain) { return domain == SampleDomain::UnitSquare ? 1.0 : 0.5; }

// Largest Poisson-disk radius of `count` samples in a 2D domain of `area` (hexagonal packing).
double max_poisson_radius(double area, size_t count) {
    return std::sqrt(area / (2.0 * std::sqrt(3.0) * static_cast<double>(count)));
}

// Max-heap of sample weights with decrease-key, addressed by sample index.
class WeightHeap {
public:
    explicit WeightHeap(std::vector<double> weights) : weights_(std::move(weights)) {
        heap_.resize(weights_.size());
        position_.resize(weights_.size());
        for (size_t i = 0; i < heap_.size(); ++i) heap_[i] = position_[i] = static_cast<uint32_t>(i);
        for (size_t i = heap_.size() / 2; i-- > 0;) sift_down(i);
    }
    uint32_t pop() {
        const uint32_t top = heap_.front();
        move(heap_.size() - 1, 0);
        heap_.pop_back();
        if (!heap_.empty()) sift_down(0);
        return top;
    }
    void decrease(uint32_t sample, double amount) {
        weights_[sample] -= amount;
        sift_down(position_[sample]);
    }

private:
    bool above(size_t a, size_t b) const {
        // Ties broken by index so the order is the same on every platform.
        const double wa = weights_[heap_[a]], wb = weights_[heap_[b]];
        return wa > wb || (wa == wb && heap_[a] < heap_[b]);
    }
    void move(size_t from, size_t to) {
        heap_[to] = heap_[from];
        position_[heap_[to]] = static_cast<uint32_t>(to);
    }
    void sift_down(size_t i) {
        for (;;) {
            size_t best = i;
            for (size_t child = 2 * i + 1; child <= 2 * i + 2 && child < heap_.size(); ++child)
                if (above(child, best)) best = child;
            if (best == i) return;
            std::swap(heap_[i], heap_[best]);
            position_[heap_[i]] = static_cast<uint32_t>(i);
            position_[heap_[best]] = static_cast<uint32_t>(best);
            i = best;
        }
    }
    std::vector<double> weights_;
    std::vector<uint32_t> heap_, position_;
};

// Neighbour lists within `radius` among `points`, found through a uniform grid of that cell size.
struct Neighbours {
    std::vector<uint32_t> offsets, indices;
    std::vector<double> distances;
};

Neighbours find_neighbours(const std::vector<glm::vec2>& points, double radius) {
    const int cells = std::max(1, static_cast<int>(std::ceil(1.0 / radius)));
    const auto cell_of = [cells](float x) { return std::clamp(static_cast<int>(x * cells), 0, cells - 1); };
    std::vector<uint32_t> cell_start(static_cast<size_t>(cells) * cells + 1, 0), sorted(points.size());
    for (const glm::vec2& p : points) ++cell_start[cell_of(p.y) * cells + cell_of(p.x) + 1];
    for (size_t c = 1; c < cell_start.size(); ++c) cell_start[c] += cell_start[c - 1];
    std::vector<uint32_t> fill(cell_start.begin(), cell_start.end() - 1);
    for (size_t i = 0; i < points.size(); ++i)
        sorted[fill[cell_of(points[i].y) * cells + cell_of(points[i].x)]++] = static_cast<uint32_t>(i);

    Neighbours result;
    // About pi (2 r_max)^2 / (area per candidate) ~ 18 neighbours per candidate; reserve for 32.
    result.indices.reserve(points.size() * 32);
    result.distances.reserve(points.size() * 32);
    result.offsets.reserve(points.size() + 1);
    result.offsets.push_back(0);
    for (size_t i = 0; i < points.size(); ++i) {
        const int cx = cell_of(points[i].x), cy = cell_of(points[i].y);
        for (int y = std::max(0, cy - 1); y <= std::min(cells - 1, cy + 1); ++y)
            for (int x = std::max(0, cx - 1); x <= std::min(cells - 1, cx + 1); ++x)
                for (uint32_t k = cell_start[y * cells + x]; k < cell_start[y * cells + x + 1]; ++k) {
                    const uint32_t j = sorted[k];
                    const double dx = double(points[j].x) - points[i].x, dy = double(points[j].y) - points[i].y;
                    const double d = std::sqrt(dx * dx + dy * dy);
                    if (j != i && d < radius) {
                        result.indices.push_back(j);
                        result.distances.push_back(d);
                    }
                }
        result.offsets.push_back(static_cast<uint32_t>(result.indices.size()));
    }
    return result;
}

// Removes samples of highest weight until `keep` remain (Yuksel 2015, Sec. 4); returns the
// survivors in input order and appends the removed ones to `removed` in removal order.
std::vector<glm::vec2> eliminate(const std::vector<glm::vec2>& points, size_t keep, double area,
                                 std::vector<glm::vec2>& removed) {
    const double r_max = max_poisson_radius(area, keep);
    const double ratio = static_cast<double>(keep) / static_cast<double>(points.size());
    const double r_min = r_max * (1.0 - std::pow(ratio, kLimitGamma)) * kLimitBeta;
    const double d_max = 2.0 * r_max;
    const Neighbours neighbours = find_neighbours(points, d_max);
    // Weight limiting: pairs closer than 2 r_min all weigh the same, so clusters do not dominate.
    std::vector<double> pair_weight(neighbours.distances.size());
    for (size_t k = 0; k < pair_weight.size(); ++k)
        pair_weight[k] = weight_of(1.0 - std::max(neighbours.distances[k], 2.0 * r_min) / d_max);
    std::vector<double> weights(points.size(), 0.0);
    for (size_t i = 0; i < points.size(); ++i)
        for (uint32_t k = neighbours.offsets[i]; k < neighbours.offsets[i + 1]; ++k) weights[i] += pair_weight[k];

    WeightHeap heap(std::move(weights));
    std::vector<char> alive(points.size(), 1);
    for (size_t left = points.size(); left > keep; --left) {
        const uint32_t worst = heap.pop();
        alive[worst] = 0;
        removed.push_back(points[worst]);
        for (uint32_t k = neighbours.offsets[worst]; k < neighbours.offsets[worst + 1]; ++k)
            if (alive[neighbours.indices[k]]) heap.decrease(neighbours.indices[k], pair_weight[k]);
    }
    std::vector<glm::vec2> survivors;
    survivors.reserve(keep);
    for (size_t i = 0; i < points.size(); ++i)
        if (alive[i]) survivors.push_back(points[i]);
    return survivors;
}

}  // namespace

std::vector<glm::vec2> progressive_blue_noise(size_t count, SampleDomain domain, uint64_t seed) {
    if (count == 0) return {};
    if (count > (size_t{1} << 26)) throw Error("blue-noise sample count " + std::to_string(count) + " is too large");
    RandomStream random(seed);
    std::vector<glm::vec2> points(count * kCandidatesPerSample);
    for (glm::vec2& p : points) {
        p = {random.next_unit(), random.next_unit()};
        // Reflecting the upper half onto the lower keeps triangle candidates uniform.
        if (domain == SampleDomain::UnitTriangle && p.x + p.y >= 1.0f) p = {1.0f - p.x, 1.0f - p.y};
    }
    const double area = domain_area(domain);
    std::vector<glm::vec2> discarded, ordered_removals;
    points = eliminate(points, count, area, discarded);
    // Progressive order: halve repeatedly; a sample removed later belongs earlier in the set.
    while (points.size() > 1) points = eliminate(points, points.size() / 2, area, ordered_removals);
    ordered_removals.push_back(points.front());
    std::reverse(ordered_removals.begin(), ordered_removals.end());
    return ordered_removals;
}

glm::vec2 triangle_to_square(glm::vec2 xi) {
    const float rest = 1.0f - xi.y;
    return {rest > 0.0f ? std::min(1.0f, xi.x / rest) : 0.0f, xi.y};
}

RootSampleSets make_root_sample_sets(size_t samples_per_set, int set_count, uint64_t seed, bool squares,
                                     bool triangles) {
    if (samples_per_set == 0 || set_count < 1) throw Error("root sample sets need at least one set of one sample");
    RootSampleSets sets;
    sets.samples_per_set = samples_per_set;
    sets.set_count = set_count;
    sets.seed = seed;
    for (int k = 0; k < set_count; ++k) {
        if (squares) {
            const auto square = progressive_blue_noise(samples_per_set, SampleDomain::UnitSquare, hash_keys(seed, 1, k));
            sets.square.insert(sets.square.end(), square.begin(), square.end());
        }
        if (triangles) {
            const auto triangle = progressive_blue_noise(samples_per_set, SampleDomain::UnitTriangle, hash_keys(seed, 2, k));
            sets.triangle.insert(sets.triangle.end(), triangle.begin(), triangle.end());
        }
    }
    return sets;
}

glm::vec2 RootSampleSets::root_coordinates(uint64_t bundle, size_t index, bool triangle_face) const {
    const uint64_t choice = hash_keys(seed, bundle, 0x726f6f74);
    const size_t set = static_cast<size_t>(choice % static_cast<uint64_t>(set_count));
    const uint32_t symmetry = static_cast<uint32_t>(choice >> 32);
    if (!triangle_face) {
        glm::vec2 p = square[set * samples_per_set + index];
        // One of the 8 symmetries of the square: optional transpose, then optional mirrors.
        if (symmetry & 1u) p = {p.y, p.x};
        if (symmetry & 2u) p.x = 1.0f - p.x;
        if (symmetry & 4u) p.y = 1.0f - p.y;
        return p;
    }
    const glm::vec2 xi = triangle[set * samples_per_set + index];
    // One of the 6 permutations of the barycentric coordinates (1 - s - t, s, t).
    const std::array<float, 3> barycentric{1.0f - xi.x - xi.y, xi.x, xi.y};
    static constexpr std::array<std::array<int, 2>, 6> kPermutations{{{1, 2}, {2, 1}, {0, 2}, {2, 0}, {0, 1}, {1, 0}}};
    const auto& pick = kPermutations[symmetry % 6];
    return triangle_to_square({std::max(0.0f, barycentric[pick[0]]), std::max(0.0f, barycentric[pick[1]])});
}

}  // namespace hairlod
