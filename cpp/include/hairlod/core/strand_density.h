#pragma once
// The strands' density on a voxel grid: their projected area per unit volume and the second moments of
// their tangents, splatted from samples along every segment. hairlod/world_occlusion.py sweeps it into the
// optical depth from each voxel out to the world, which the viewport preview's world light passes through.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace hairlod {

// The density's fields, in this order: the projected area 2 r l per unit volume (r the segment's mean
// radius, l its length), then that weighted by the tangent's products t_x t_x, t_y t_y, t_z t_z, t_x t_y,
// t_x t_z, t_y t_z.
inline constexpr int kStrandDensityFields = 7;

struct StrandDensityOptions {
    glm::dvec3 lower{0.0};   // a box holding every point (the strands' bounding box)
    glm::dvec3 upper{0.0};
    int resolution = 48;     // voxels along the box's largest extent (>= 1)
    int64_t max_samples = 250000;  // samples splatted, at most about this many (>= 1)
    double sample_spacing = 0.5;   // voxels between samples along a segment, at most (> 0)
};

struct StrandDensity {
    double voxel = 1.0;          // the cubic voxels' edge; the box's largest extent over the resolution
    std::array<int, 3> shape{};  // voxels per axis: the box's, plus one on every side
    int64_t strand_step = 1;     // every strand_step-th strand was sampled, standing for strand_step strands
    // [kStrandDensityFields][shape x][shape y][shape z], z fastest. Voxel (i, j, k) is centred at
    // lower + ((i, j, k) - 0.5) voxel: the voxel on each side of the box holds what the points on its
    // faces spread outwards.
    std::vector<double> fields;
};

// Each segment of every strand_step-th strand (strand_step the least that keeps the samples to
// max_samples, first from the point count, then from the samples' count) sampled at the midpoints of
// max(1, ceil(l / (sample_spacing voxel))) equal pieces, each sample adding its piece's share of the
// segment's area (times strand_step) to the 8 voxels around it by trilinear weights. Hair with no
// extent gets voxels of 1. Throws hairlod::Error for offsets that do not run from 0 to the point count
// through rising values, a radius per point missing, a point or radius of a strand it samples that is
// not finite, or options out of range.
StrandDensity strand_density(std::span<const glm::vec3> points, std::span<const int64_t> offsets,
                             std::span<const float> radius, const StrandDensityOptions& options);

}  // namespace hairlod
