// Cost of one BCSDF evaluation per model (single thread, 1024 fixed random direction pairs).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/model_factory.h"

namespace {

using namespace hairlod::bcsdf;

struct Pairs {
    std::vector<glm::dvec3> wi, wo;
    std::vector<double> h;
};

const Pairs& pairs() {
    static const Pairs p = [] {
        Pairs result;
        std::mt19937_64 rng(42);
        std::normal_distribution<double> n;
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (int k = 0; k < 1024; ++k) {
            result.wi.push_back({n(rng), n(rng), n(rng)});
            result.wo.push_back({n(rng), n(rng), n(rng)});
            result.h.push_back(u(rng));
        }
        return result;
    }();
    return p;
}

void run(benchmark::State& state, const FiberBcsdf& bcsdf) {
    const Pairs& p = pairs();
    for (auto _ : state)
        for (size_t k = 0; k < p.wi.size(); ++k) benchmark::DoNotOptimize(bcsdf.eval(p.wi[k], p.wo[k]));
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(p.wi.size()));
}

void BM_Model(benchmark::State& state, BcsdfModel model) { run(state, *make_bcsdf(model, HairParams{})); }

void BM_ChiangNearField(benchmark::State& state) {
    const ChiangBcsdf bcsdf(HairParams{});
    const Pairs& p = pairs();
    for (auto _ : state)
        for (size_t k = 0; k < p.wi.size(); ++k) benchmark::DoNotOptimize(bcsdf.eval_lobes(p.wi[k], p.wo[k], p.h[k]));
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(p.wi.size()));
}

BENCHMARK(BM_ChiangNearField)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Model, chiang_far_field, BcsdfModel::Chiang)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Model, huang, BcsdfModel::Huang)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Model, marschner, BcsdfModel::Marschner)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Model, fiber_rtd, BcsdfModel::FiberRtd)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Model, realtime, BcsdfModel::Realtime)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Model, aggregated, BcsdfModel::Aggregated)->Unit(benchmark::kMicrosecond);

}  // namespace
