// Arc-length resampling throughput (points written per second).
#include <benchmark/benchmark.h>

#include "hairlod/curves/resample.h"
#include "synthetic_strands.h"

namespace hairlod {
namespace {

void BM_ResampleStrands(benchmark::State& state) {
    const StrandSet strands = bench::synthetic_strands(static_cast<size_t>(state.range(0)), 32);
    const ResampleOptions options{.points_per_curve = 16};
    for (auto _ : state) benchmark::DoNotOptimize(resample_strands(strands, options));
    state.SetItemsProcessed(state.iterations() * state.range(0) * options.points_per_curve);
}
BENCHMARK(BM_ResampleStrands)->Arg(10'000)->Arg(100'000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace hairlod
