#pragma once
// Baking the lookup tables the viewport shader needs to evaluate the aggregated BCSDF
// (hair-lod-aggregated-bcsdf.txt, Eq. 1 and 6-15) with a few texture fetches. The longitudinal and
// azimuthal lobes M_p, N_p are closed forms (Huang 2025 Eq. 8; M_p in the rough-cone form of fiber_rtd.h) and are
// evaluated in the shader; only the terms without a closed form are baked: the fibre's lobe
// attenuations A_R, A_TT, A_D over theta_o, the dual-scattering terms over theta_d, and the aggregated
// attenuations over (theta_d, n) for n up to the largest hair count in use.
#include <cmath>
#include <string>
#include <vector>

#include "hairlod/bcsdf/hair_params.h"

namespace hairlod::bcsdf {

// One axis of a table: `samples` values from begin to end inclusive (texel centres on the nodes).
struct BakeAxis {
    std::string name;
    double begin = 0.0;
    double end = 1.0;
    int samples = 2;
    bool log_scale = false;  // nodes uniform in log(value) instead of value
    double at(int k) const {
        const double t = double(k) / (samples - 1);
        return log_scale ? begin * std::pow(end / begin, t) : begin + (end - begin) * t;
    }
};

struct BakedTable {
    std::string name;
    std::string equation;               // what it tabulates, with its source
    std::vector<BakeAxis> axes;         // axes[0] along the image width, axes[1] (if any) along the height
    std::vector<std::string> channels;  // EXR channel names
    std::vector<float> values;          // rows of axes[0].samples pixels of channels.size() floats
    int width() const { return axes[0].samples; }
    int height() const { return axes.size() > 1 ? axes[1].samples : 1; }
};

struct BakeOptions {
    int theta_samples = 64;        // theta_d samples (>= 2)
    int hair_count_samples = 64;   // n samples (>= 2)
    double max_hair_count = 64.0;  // n in [1, max_hair_count] (>= 1)
    // theta_d samples of the per-hair dual-scattering table (aggregated_table) the baked tables are
    // interpolated from: its linear interpolation is the LUT's error floor (bench bcsdf reports it).
    int table_samples = 65;
};

// The tables of the aggregated model for `params` (validated), computed in parallel (TBB).
std::vector<BakedTable> bake_aggregated(const HairParams& params, const BakeOptions& options = {});

struct CircularGaussianTables;

// Xu et al. 2011's global tables (Sec. 5) as BakedTables: C_k (Eq. 14, k = 0..6) over (phi, lambda'),
// H_k^TT (Xu 2011 Eq. 19) and H_k^TRT (Eq. 23), k = 0, 2, 4, over (theta_d, eta'); lambda' and eta' log-uniform.
std::vector<BakedTable> bake_circular_gaussian(const CircularGaussianTables& tables);

}  // namespace hairlod::bcsdf
