// Strand generation from a hair mesh: 100k strands x 33 vertices with every styling operation
// (issue 4 target: under 50 ms on a 2-core machine). Counters: vertices per second, the ratio of the
// generation time to a plain copy of an output-sized array timed in the same run, and storage bytes
// of the hair mesh + styling parameters against the generated strands. BM_VertexLod reports speed
// against error for vertex LoD: vertices and time per level against the distance from the full
// strands.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "hairlod/core/strand_metrics.h"
#include "hairlod/hairmesh/generate.h"

namespace hairlod {
namespace {

// A scalp cap (a sphere of radius 10 above the equator, 16 x 8 quads) extruded into 5 layers that
// leave along the normal and fall under a gravity-like bend.
HairMesh scalp_hair_mesh() {
    constexpr int kAround = 16, kUp = 8, kLayers = 5;
    std::vector<glm::vec3> root;
    for (int j = 0; j <= kUp; ++j)
        for (int i = 0; i < kAround; ++i) {
            const float theta = 0.1f + 1.3f * j / kUp, phi = 2.0f * std::numbers::pi_v<float> * i / kAround;
            root.emplace_back(10.0f * std::sin(theta) * std::cos(phi), 10.0f * std::sin(theta) * std::sin(phi), 10.0f * std::cos(theta));
        }
    std::vector<glm::vec3> positions;
    for (int layer = 0; layer < kLayers; ++layer)
        for (const glm::vec3& p : root) positions.push_back(p * (1.0f + 0.08f * layer) - glm::vec3(0, 0, 1.5f * layer * layer));
    std::vector<int32_t> sizes, indices;
    for (int j = 0; j < kUp; ++j)
        for (int i = 0; i < kAround; ++i) {
            const int a = j * kAround + i, b = j * kAround + (i + 1) % kAround;
            sizes.push_back(4);
            indices.insert(indices.end(), {a, b, b + kAround, a + kAround});
        }
    return make_hair_mesh(std::move(positions), root.size(), sizes, indices);
}

GenerateOptions full_options() {
    GenerateOptions options;
    options.count = 100'000;
    options.vertices = 33;
    options.radius = 0.01f;
    options.seed = 1;
    options.styling = {Curl{0.3f, 0.4f, 0.5f}, Wave{0.5f, 0.1f, 0.5f}, Twist{0.02f},
                       Clump{0.4f, 2.0f},      Frizz{0.05f, 2.0f},      Trim{0.2f}};
    return options;
}

size_t strand_bytes(const StrandSet& strands) {
    size_t bytes = strands.points.size() * sizeof(glm::vec3) + strands.radius.size() * sizeof(float) +
                   strands.offsets.size() * sizeof(int64_t);
    for (const auto& [name, attribute] : strands.attributes) bytes += attribute.values.size() * sizeof(float);
    return bytes;
}

size_t hair_mesh_bytes(const HairMesh& mesh, const GenerateOptions& options) {
    return mesh.positions.size() * sizeof(glm::vec3) + mesh.face_offsets.size() * sizeof(int32_t) +
           mesh.corner_vertices.size() * sizeof(int32_t) + mesh.corner_uv.size() * sizeof(glm::vec2) +
           mesh.w.size() * sizeof(float) + options.styling.size() * sizeof(StylingOperation) + sizeof(GenerateOptions);
}

// Median seconds of copying `bytes` between two warm buffers.
double copy_seconds(size_t bytes) {
    std::vector<char> source(bytes, 1), target(bytes, 0);
    std::vector<double> times;
    for (int i = 0; i < 7; ++i) {
        const auto start = std::chrono::steady_clock::now();
        std::memcpy(target.data(), source.data(), bytes);
        benchmark::DoNotOptimize(target.data());
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
}

void BM_GenerateStrands(benchmark::State& state) {
    const HairMesh mesh = scalp_hair_mesh();
    GenerateOptions options = full_options();
    if (state.range(0) == 0) options.styling.clear();
    // Frames and root sample sets depend only on the mesh and seed: built once, as a viewer would.
    const StylingFrames frames = compute_styling_frames(mesh);
    const RootSampleSets samples = root_sample_sets_for(mesh, options);
    // The output is reused across iterations, as a viewer regenerating every frame does; the first
    // generation (allocation and page faults of ~130 MB) is left out.
    StrandSet strands;
    generate_strands(mesh, frames, samples, options, strands);
    double seconds = 0.0;
    for (auto _ : state) {
        const auto start = std::chrono::steady_clock::now();
        generate_strands(mesh, frames, samples, options, strands);
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        benchmark::DoNotOptimize(strands.points.data());
    }
    const size_t output_bytes = strand_bytes(strands);
    const double per_iteration = seconds / static_cast<double>(state.iterations());
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(strands.point_count()));
    state.counters["vs_copy"] = per_iteration / copy_seconds(output_bytes);
    state.counters["strand_MB"] = static_cast<double>(output_bytes) / 1e6;
    state.counters["mesh_KB"] = static_cast<double>(hair_mesh_bytes(mesh, options)) / 1e3;
}
BENCHMARK(BM_GenerateStrands)->ArgName("styling")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

// Mean and largest distance of each LoD strand, read as a polyline over its curve parameter, from
// the full strand at the full strand's vertices, relative to the bounding-box diagonal.
std::pair<double, double> vertex_lod_error(const StrandSet& full, const StrandSet& reduced) {
    double sum = 0.0, largest = 0.0;
    for (size_t c = 0; c < full.curve_count(); ++c) {
        const auto exact = full.curve_points(c), coarse = reduced.curve_points(c);
        const double step = static_cast<double>(coarse.size() - 1) / static_cast<double>(exact.size() - 1);
        for (size_t k = 0; k < exact.size(); ++k) {
            const double x = step * static_cast<double>(k);
            const size_t i = std::min(static_cast<size_t>(x), coarse.size() - 2);
            const glm::vec3 p = glm::mix(coarse[i], coarse[i + 1], static_cast<float>(x - static_cast<double>(i)));
            const double d = glm::distance(p, exact[k]);
            sum += d;
            largest = std::max(largest, d);
        }
    }
    const double diagonal = bounding_box(full.points).diagonal();
    return {sum / static_cast<double>(full.point_count()) / diagonal, largest / diagonal};
}

void BM_VertexLod(benchmark::State& state) {
    const HairMesh mesh = scalp_hair_mesh();
    GenerateOptions options = full_options();
    options.count = 10'000;
    const StylingFrames frames = compute_styling_frames(mesh);
    const RootSampleSets samples = root_sample_sets_for(mesh, options);
    StrandSet full, strands;
    generate_strands(mesh, frames, samples, options, full);
    options.vertex_lod = static_cast<float>(state.range(0)) / 64.0f;
    for (auto _ : state) {
        generate_strands(mesh, frames, samples, options, strands);
        benchmark::DoNotOptimize(strands.points.data());
    }
    const auto [mean_error, max_error] = vertex_lod_error(full, strands);
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(strands.point_count()));
    state.counters["vertices"] = static_cast<double>(strands.curve_size(0));
    state.counters["mean_error"] = mean_error;
    state.counters["max_error"] = max_error;
}
// L = 64/64, 40/64 (a morph under way), 32/64, 16/64, 8/64, 2/64.
BENCHMARK(BM_VertexLod)->ArgName("L64")->Arg(64)->Arg(40)->Arg(32)->Arg(16)->Arg(8)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RootSampleSets(benchmark::State& state) {
    const HairMesh mesh = scalp_hair_mesh();
    const GenerateOptions options = full_options();
    for (auto _ : state) benchmark::DoNotOptimize(root_sample_sets_for(mesh, options));
}
BENCHMARK(BM_RootSampleSets)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

}  // namespace
}  // namespace hairlod
