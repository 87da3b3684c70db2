// LoD build stages for 100k strands x 32 points, 256 guides, 6 levels (issue 5: at most 5 s in
// total), the per-frame selection (at most 0.2 ms for about 256 clusters), and a viewport's update over
// a dolly with warm and with evicted caches.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "hairlod/lod/lod_asset.h"
#include "hairlod/lod/selection.h"
#include "hairlod/lod/view_selection.h"
#include "synthetic_strands.h"

namespace hairlod {
namespace {

void BM_BuildLod(benchmark::State& state) {
    const StrandSet strands = bench::synthetic_strands(static_cast<size_t>(state.range(0)), 32);
    const LodOptions options{.guides = static_cast<int>(state.range(1)), .levels = 6};
    LodAsset asset;
    for (auto _ : state) {
        asset = build_lod(strands, options);
        benchmark::DoNotOptimize(asset);
    }
    const size_t strand_bytes = strands.points.size() * sizeof(glm::vec3) + strands.radius.size() * sizeof(float) +
                                strands.offsets.size() * sizeof(int64_t);
    state.counters["resample_s"] = asset.timings.resample;
    state.counters["kmeans_s"] = asset.timings.kmeans;
    state.counters["l0_s"] = asset.timings.clusters;
    state.counters["levels_s"] = asset.timings.levels;
    state.counters["fitting_s"] = asset.timings.fitting;
    state.counters["weights_s"] = asset.timings.weights;
    state.counters["l0_clusters"] = static_cast<double>(asset.cluster_count());
    state.counters["thick_levels"] = static_cast<double>(asset.thick_levels.size());
    state.counters["extra_memory"] = static_cast<double>(asset.memory_bytes()) / static_cast<double>(strand_bytes);
    for (size_t l = 0; l < asset.thick_levels.size(); ++l) {
        state.counters["coverage_L" + std::to_string(l)] = asset.thick_levels[l].coverage;
        state.counters["hairs_L" + std::to_string(l)] = static_cast<double>(asset.thick_levels[l].hair_count());
        if (l > 0)
            state.counters["area_ratio_L" + std::to_string(l)] =
                asset.thick_levels[l - 1].mean_area / asset.thick_levels[l].mean_area;
    }
}
BENCHMARK(BM_BuildLod)->Args({100'000, 256})->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// Camera looking at the synthetic head (unit sphere, strands hanging along -z) from `distance`.
Camera camera_at(float distance) {
    Camera camera;
    camera.view = glm::lookAt(glm::vec3(distance, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, -0.5f), glm::vec3(0, 0, 1));
    camera.projection = glm::perspective(glm::radians(40.0f), 16.0f / 9.0f, 0.05f, 100.0f);
    camera.viewport = {1920.0f, 1080.0f};
    return camera;
}

// Arguments: strands, guides, camera distance. 64 guides give about 256 L0 clusters.
void BM_SelectDeferred(benchmark::State& state) {
    const StrandSet strands = bench::synthetic_strands(static_cast<size_t>(state.range(0)), 32);
    const LodAsset asset = build_lod(strands, {.guides = static_cast<int>(state.range(1)), .levels = 6});
    const LodGeometry geometry = asset.rest_geometry();
    const Camera camera = camera_at(static_cast<float>(state.range(2)));
    Selection selection = select_initial(asset, geometry, camera, 2.0f);
    for (auto _ : state) {
        select_deferred_in_place(asset, geometry, camera, 2.0f, selection);  // no allocation per frame
        benchmark::DoNotOptimize(selection.level.data());
    }
    double mean_level = 0.0;
    for (uint8_t level : selection.level) mean_level += level;
    state.counters["l0_clusters"] = static_cast<double>(asset.cluster_count());
    state.counters["mean_level"] = mean_level / static_cast<double>(selection.level.size());
    state.counters["draws"] = static_cast<double>(selection.draws.size());
}
BENCHMARK(BM_SelectDeferred)->Args({20'000, 64, 30})->Args({20'000, 64, 6})->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_SelectInitial(benchmark::State& state) {
    const StrandSet strands = bench::synthetic_strands(static_cast<size_t>(state.range(0)), 32);
    const LodAsset asset = build_lod(strands, {.guides = static_cast<int>(state.range(1)), .levels = 6});
    const LodGeometry geometry = asset.rest_geometry();
    const Camera camera = camera_at(static_cast<float>(state.range(2)));
    for (auto _ : state) benchmark::DoNotOptimize(select_initial(asset, geometry, camera, 2.0f));
}
BENCHMARK(BM_SelectInitial)->Args({20'000, 64, 30})->Args({20'000, 64, 6})->Unit(benchmark::kMicrosecond)->UseRealTime();

// A viewport's per-frame update (ViewSelection::update: Huang 2025 Eq. 16 until stable, the draw list) over a
// dolly from 1.2 to 30 units, every frame changing the selection. Arguments: strands, guides, and
// whether the caches are evicted between frames (1), as a viewport's drawing of the hair does in
// Blender: there the update reads its geometry from memory, not from the cache.
void BM_ViewSelectionDolly(benchmark::State& state) {
    const StrandSet strands = bench::synthetic_strands(static_cast<size_t>(state.range(0)), 32);
    const LodAsset asset = build_lod(strands, {.guides = static_cast<int>(state.range(1)), .levels = 6});
    const bool cold = state.range(2) != 0;
    constexpr int kFrames = 24;
    std::vector<Camera> cameras;
    for (int frame = 0; frame < kFrames; ++frame)
        cameras.push_back(camera_at(1.2f * std::pow(25.0f, static_cast<float>(frame) / (kFrames - 1))));
    ViewSelection view(asset, asset.rest_geometry());
    std::vector<uint8_t> evict(cold ? size_t{64} << 20 : 0, 1);
    size_t frame = 0;
    for (auto _ : state) {
        if (cold) {
            state.PauseTiming();
            for (size_t i = 0; i < evict.size(); i += 64) evict[i] = static_cast<uint8_t>(evict[i] + 1);
            benchmark::DoNotOptimize(evict.data());
            state.ResumeTiming();
        }
        if (frame % kFrames == 0) view.reset();  // each dolly starts from a new view
        benchmark::DoNotOptimize(view.update(cameras[frame % kFrames], 2.0f));
        ++frame;
    }
    state.counters["l0_clusters"] = static_cast<double>(asset.cluster_count());
}
BENCHMARK(BM_ViewSelectionDolly)->Args({100'000, 256, 0})->Args({100'000, 256, 1})->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
}  // namespace hairlod
