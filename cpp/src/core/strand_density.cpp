#include "hairlod/core/strand_density.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

int64_t ceil_div(int64_t a, int64_t b) { return (a + b - 1) / b; }

// Samples of a segment `length` long, at most `spacing` apart.
int64_t segment_samples(double length, double spacing) {
    return std::max<int64_t>(static_cast<int64_t>(std::ceil(length / spacing)), 1);
}

void check_input(std::span<const glm::vec3> points, std::span<const int64_t> offsets, std::span<const float> radius,
                 const StrandDensityOptions& options) {
    if (options.resolution < 1 || options.max_samples < 1)
        throw Error("strand density: resolution and max_samples must be >= 1, got " + std::to_string(options.resolution) +
                    ", " + std::to_string(options.max_samples));
    if (!(options.sample_spacing > 0.0) || !std::isfinite(options.sample_spacing))
        throw Error("strand density: sample_spacing must be finite and > 0");
    if (offsets.empty() || offsets.front() != 0 || offsets.back() != static_cast<int64_t>(points.size()))
        throw Error("strand density: offsets must run from 0 to " + std::to_string(points.size()));
    for (size_t c = 0; c + 1 < offsets.size(); ++c)
        if (offsets[c + 1] <= offsets[c]) throw Error("strand density: offsets must rise (every strand holds a point)");
    if (radius.size() != points.size())
        throw Error("strand density: radius must have one value per point (" + std::to_string(points.size()) + "), got " +
                    std::to_string(radius.size()));
    for (int axis = 0; axis < 3; ++axis)
        if (!std::isfinite(options.lower[axis]) || !std::isfinite(options.upper[axis]) ||
            options.upper[axis] < options.lower[axis])
            throw Error("strand density: the box must be finite, its upper corner at or above its lower");
}

}  // namespace

StrandDensity strand_density(std::span<const glm::vec3> points, std::span<const int64_t> offsets,
                             std::span<const float> radius, const StrandDensityOptions& options) {
    check_input(points, offsets, radius, options);
    StrandDensity result;
    const glm::dvec3 extent = options.upper - options.lower;
    const double largest = std::max({extent.x, extent.y, extent.z});
    // Hair with no extent (every point in one place) occludes nothing measurable: voxels of 1.
    result.voxel = largest > 0.0 ? largest / options.resolution : 1.0;
    std::array<int, 3> inner{};
    for (int axis = 0; axis < 3; ++axis) {
        inner[axis] = std::max(static_cast<int>(std::ceil(extent[axis] / result.voxel - 1e-9)), 1);
        result.shape[axis] = inner[axis] + 2;
    }
    const size_t cells = static_cast<size_t>(result.shape[0]) * result.shape[1] * result.shape[2];
    const int64_t strand_count = static_cast<int64_t>(offsets.size()) - 1;
    const double spacing = options.sample_spacing * result.voxel;

    // Every k-th strand stands for k: first k to keep the points to max_samples, then to keep the
    // samples of those strands to it. The strands splatted below are among those counted here, whose
    // points and radii are checked on the way: a point that is not finite has no voxel.
    const int64_t point_step = std::max<int64_t>(ceil_div(static_cast<int64_t>(points.size()), options.max_samples), 1);
    std::atomic<bool> finite{true};
    const int64_t total_samples = tbb::parallel_reduce(
        tbb::blocked_range<int64_t>(0, ceil_div(strand_count, point_step)), int64_t{0},
        [&](const tbb::blocked_range<int64_t>& range, int64_t sum) {
            for (int64_t kept = range.begin(); kept != range.end(); ++kept) {
                const int64_t c = kept * point_step;
                for (int64_t i = offsets[c]; i < offsets[c + 1]; ++i) {
                    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y) || !std::isfinite(points[i].z) ||
                        !std::isfinite(radius[i]))
                        finite = false;
                    else if (i + 1 < offsets[c + 1])
                        sum += segment_samples(glm::length(glm::dvec3(points[i + 1]) - glm::dvec3(points[i])), spacing);
                }
            }
            return sum;
        },
        [](int64_t a, int64_t b) { return a + b; });
    if (!finite) throw Error("strand density: points and radii must be finite");
    result.strand_step = point_step * std::max<int64_t>(ceil_div(total_samples, options.max_samples), 1);

    const std::array<size_t, 3> stride{static_cast<size_t>(result.shape[1]) * result.shape[2],
                                       static_cast<size_t>(result.shape[2]), 1};
    const double inverse_voxel = 1.0 / result.voxel;
    const double per_volume = static_cast<double>(result.strand_step) / (result.voxel * result.voxel * result.voxel);
    tbb::enumerable_thread_specific<std::vector<double>> grids(
        [&] { return std::vector<double>(kStrandDensityFields * cells, 0.0); });
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, ceil_div(strand_count, result.strand_step), 64),
                      [&](const tbb::blocked_range<int64_t>& range) {
        std::vector<double>& grid = grids.local();
        for (int64_t kept = range.begin(); kept != range.end(); ++kept) {
            const int64_t c = kept * result.strand_step;
            for (int64_t i = offsets[c]; i + 1 < offsets[c + 1]; ++i) {
                const glm::dvec3 start(points[i]);
                const glm::dvec3 step = glm::dvec3(points[i + 1]) - start;
                const double length = glm::length(step);
                const int64_t samples = segment_samples(length, spacing);
                const glm::dvec3 t = step / std::max(length, 1e-300);
                const double weight = (static_cast<double>(radius[i]) + radius[i + 1]) * length * per_volume /
                                      static_cast<double>(samples);
                const double values[kStrandDensityFields] = {1.0, t.x * t.x, t.y * t.y, t.z * t.z, t.x * t.y, t.x * t.z, t.y * t.z};
                for (int64_t s = 0; s < samples; ++s) {
                    const glm::dvec3 p = start + ((static_cast<double>(s) + 0.5) / static_cast<double>(samples)) * step;
                    // In units of voxel centres, the margin's centre at 0.
                    size_t base[3];
                    double frac[3];
                    for (int axis = 0; axis < 3; ++axis) {
                        const double cell = std::clamp((p[axis] - options.lower[axis]) * inverse_voxel + 0.5, 0.5,
                                                       inner[axis] + 0.5);
                        const int index = std::min(static_cast<int>(cell), inner[axis]);
                        base[axis] = static_cast<size_t>(index);
                        frac[axis] = cell - index;
                    }
                    for (int dx = 0; dx < 2; ++dx) {
                        const double wx = dx ? frac[0] : 1.0 - frac[0];
                        for (int dy = 0; dy < 2; ++dy) {
                            const double wxy = wx * (dy ? frac[1] : 1.0 - frac[1]);
                            for (int dz = 0; dz < 2; ++dz) {
                                const double corner = weight * wxy * (dz ? frac[2] : 1.0 - frac[2]);
                                const size_t cell_index = (base[0] + dx) * stride[0] + (base[1] + dy) * stride[1] + base[2] + dz;
                                for (int f = 0; f < kStrandDensityFields; ++f) grid[f * cells + cell_index] += corner * values[f];
                            }
                        }
                    }
                }
            }
        }
    });
    result.fields.assign(kStrandDensityFields * cells, 0.0);
    for (const std::vector<double>& grid : grids)
        tbb::parallel_for(size_t{0}, result.fields.size(), [&](size_t i) { result.fields[i] += grid[i]; });
    return result;
}

}  // namespace hairlod
