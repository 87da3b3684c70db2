#pragma once
// Baking the lookup tables the viewport shader needs to evaluate the aggregated BCSDF
// (hair-lod-aggregated-bcsdf.txt, Eq. 1 and 6-15) with a few texture fetches. The longitudinal and
// azimuthal lobes M_p, N_p are closed-form Gaussians (Eq. 8) and are evaluated in the shader; only
// the terms without a closed form are baked: the fibre's lobe attenuations A_R, A_TT, A_D over
// theta_d, the dual-scattering terms over theta_d, and the aggregated attenuations over (theta_d, n)
// for n up to the largest hair count in use.
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
    double at(int k) const { return begin + (end - begin) * k / (samples - 1); }
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
    int table_samples = 33;        // theta_d samples of the aggregated model's own table (aggregated_table)
};

// The tables of the aggregated model for `params` (validated), computed in parallel (TBB).
std::vector<BakedTable> bake_aggregated(const HairParams& params, const BakeOptions& options = {});

}  // namespace hairlod::bcsdf
