#include "hairlod/bcsdf/bcsdf.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/chiang.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

glm::dvec3 LobeValues::sum() const {
    glm::dvec3 total(0.0);
    for (int p = 0; p < count; ++p) total += value[p];
    return total;
}

LobeValues& LobeValues::operator+=(const LobeValues& other) {
    count = std::max(count, other.count);
    for (int p = 0; p < kMaxLobes; ++p) value[p] += other.value[p];
    return *this;
}

LobeValues& LobeValues::operator-=(const LobeValues& other) {
    count = std::max(count, other.count);
    for (int p = 0; p < kMaxLobes; ++p) value[p] -= other.value[p];
    return *this;
}

double magnitude(const LobeValues& lobes) {
    double m = 0.0;
    for (int p = 0; p < lobes.count; ++p)
        m = std::max({m, std::abs(lobes.value[p].x), std::abs(lobes.value[p].y), std::abs(lobes.value[p].z)});
    return m;
}

LobeValues operator*(double w, LobeValues a) {
    for (auto& v : a.value) v *= w;
    return a;
}

namespace {

void check_sizes(size_t wi, size_t wo, size_t out) {
    if (wi != wo || wi != out)
        throw Error("wi, wo and the output need the same number of directions, got " + std::to_string(wi) + ", " +
                    std::to_string(wo) + " and " + std::to_string(out));
}

template <typename Evaluate>
void parallel_evaluate(size_t count, Evaluate&& evaluate_one) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t k = range.begin(); k != range.end(); ++k) evaluate_one(k);
    });
}

}  // namespace

void evaluate(const FiberBcsdf& bcsdf, std::span<const glm::vec3> wi, std::span<const glm::vec3> wo,
              std::span<glm::vec3> out) {
    check_sizes(wi.size(), wo.size(), out.size());
    parallel_evaluate(wi.size(), [&](size_t k) { out[k] = glm::vec3(bcsdf.eval(glm::dvec3(wi[k]), glm::dvec3(wo[k]))); });
}

void evaluate_near_field(const ChiangBcsdf& bcsdf, std::span<const glm::vec3> wi, std::span<const glm::vec3> wo,
                         std::span<const float> h, std::span<glm::vec3> out) {
    check_sizes(wi.size(), wo.size(), out.size());
    if (h.size() != wi.size())
        throw Error("h needs one offset per direction pair, got " + std::to_string(h.size()) + " for " +
                    std::to_string(wi.size()));
    parallel_evaluate(wi.size(), [&](size_t k) {
        out[k] = glm::vec3(bcsdf.eval_lobes(glm::dvec3(wi[k]), glm::dvec3(wo[k]), double(h[k])).sum());
    });
}

}  // namespace hairlod::bcsdf
