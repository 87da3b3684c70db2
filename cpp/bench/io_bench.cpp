// .hair read/write throughput for 100k strands x 32 points, in memory and through files.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "hairlod/io/cyhair.h"
#include "hairlod/io/hair_file.h"
#include "synthetic_strands.h"

namespace hairlod {
namespace {

constexpr size_t kCurves = 100'000;
constexpr size_t kPointsPerCurve = 32;

const StrandSet& bench_strands() {
    static const StrandSet strands = bench::synthetic_strands(kCurves, kPointsPerCurve);
    return strands;
}

void report_throughput(benchmark::State& state, size_t bytes) {
    state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes));
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kCurves * kPointsPerCurve));
}

void BM_CyHairEncode(benchmark::State& state) {
    bench_strands();  // generate the input outside the timed loop
    size_t bytes = 0;
    for (auto _ : state) {
        const std::vector<std::byte> encoded = io::write_cyhair(bench_strands());
        bytes = encoded.size();
        benchmark::DoNotOptimize(encoded.data());
    }
    report_throughput(state, bytes);
}

void BM_CyHairDecode(benchmark::State& state) {
    const std::vector<std::byte> encoded = io::write_cyhair(bench_strands());
    for (auto _ : state) benchmark::DoNotOptimize(io::read_cyhair(encoded));
    report_throughput(state, encoded.size());
}

std::filesystem::path bench_file() {
    return std::filesystem::temp_directory_path() / "hairlod_io_bench.hair";
}

void BM_HairFileWrite(benchmark::State& state) {
    bench_strands();
    for (auto _ : state) io::write_hair_file(bench_file(), bench_strands());
    report_throughput(state, std::filesystem::file_size(bench_file()));
}

void BM_HairFileRead(benchmark::State& state) {
    io::write_hair_file(bench_file(), bench_strands());
    for (auto _ : state) benchmark::DoNotOptimize(io::read_hair_file(bench_file()));
    report_throughput(state, std::filesystem::file_size(bench_file()));
    std::filesystem::remove(bench_file());
}

// Baseline for the ratios: a fresh buffer of the file's size filled by one copy. On this VM the
// page faults of fresh allocations dominate, so this is the floor for any decoder.
void BM_AllocateAndCopyBaseline(benchmark::State& state) {
    const std::vector<std::byte> encoded = io::write_cyhair(bench_strands());
    for (auto _ : state) {
        std::vector<std::byte> copy(encoded.begin(), encoded.end());
        benchmark::DoNotOptimize(copy.data());
    }
    report_throughput(state, encoded.size());
}

BENCHMARK(BM_AllocateAndCopyBaseline)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CyHairEncode)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CyHairDecode)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_HairFileWrite)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_HairFileRead)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace hairlod
