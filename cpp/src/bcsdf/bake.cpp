#include "hairlod/bcsdf/bake.h"

#include <cmath>
#include <numbers>
#include <string>

#include <glm/exponential.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/aggregated.h"
#include "hairlod/bcsdf/circular_gaussian.h"
#include "hairlod/bcsdf/fiber_rtd.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;

// Channel names "<prefix>.R", "<prefix>.G", "<prefix>.B" for each prefix.
std::vector<std::string> rgb_channels(std::initializer_list<const char*> prefixes) {
    std::vector<std::string> names;
    for (const char* prefix : prefixes)
        for (const char* c : {".R", ".G", ".B"}) names.push_back(std::string(prefix) + c);
    return names;
}

BakedTable make_table(std::string name, std::string equation, std::vector<BakeAxis> axes,
                      std::vector<std::string> channels) {
    BakedTable table{std::move(name), std::move(equation), std::move(axes), std::move(channels), {}};
    table.values.resize(static_cast<size_t>(table.width()) * table.height() * table.channels.size());
    return table;
}

// Writes RGB values into a pixel's channels starting at channel `first`.
void put(BakedTable& table, int x, int y, size_t first, const glm::dvec3& v) {
    const size_t base = (static_cast<size_t>(y) * table.width() + x) * table.channels.size() + first;
    for (int c = 0; c < 3; ++c) table.values[base + c] = static_cast<float>(v[c]);
}

}  // namespace

std::vector<BakedTable> bake_aggregated(const HairParams& params, const BakeOptions& options) {
    if (options.theta_samples < 2) throw Error("theta_samples must be >= 2, got " + std::to_string(options.theta_samples));
    if (options.hair_count_samples < 2)
        throw Error("hair_count_samples must be >= 2, got " + std::to_string(options.hair_count_samples));
    if (!(std::isfinite(options.max_hair_count) && options.max_hair_count >= 1.0))
        throw Error("max_hair_count must be finite and >= 1, got " + std::to_string(options.max_hair_count));
    if (options.table_samples < 3) throw Error("table_samples must be >= 3, got " + std::to_string(options.table_samples));
    const FiberRtdBcsdf fiber(params);
    const AggregatedTable per_hair = aggregated_table(fiber, options.table_samples);
    const BakeAxis theta_outgoing{"theta_o", 0.0, 0.5 * kPi, options.theta_samples};
    const BakeAxis theta_full{"theta_d", -0.5 * kPi, 0.5 * kPi, options.theta_samples};
    // n = 1 is an exact node; a single-valued range still needs two texels.
    const BakeAxis count{"n", 1.0, std::max(options.max_hair_count, 1.0 + 1e-6), options.hair_count_samples};

    std::vector<BakedTable> tables;
    tables.push_back(make_table("fiber_attenuation",
                                "A_R, A_TT, A_D(theta_o) of the R/TT/D fibre (Huang et al. 2025, Eq. 1; "
                                "h-averaged attenuations, even in theta_o)",
                                {theta_outgoing}, rgb_channels({"A_R", "A_TT", "A_D"})));
    tables.push_back(make_table("dual_scattering",
                                "a_f, a_b (Xu et al. 2011, Eq. 32-33), A_1, A_3, Delta_b, sigma_b (Zinke et al. 2008, "
                                "Sec. 4), sigma_f^2 (Huang et al. 2025, Eq. 9) and beta_f^2 (Zinke et al. 2008) of the fibre at theta_d",
                                {theta_full},
                                rgb_channels({"a_f", "a_b", "A_1", "A_3", "delta_b", "sigma_b", "sigma_f2", "beta_f2"})));
    tables.push_back(make_table("aggregated_attenuation",
                                "a_F^(n-1) (Huang et al. 2025, Eq. 7), A_1+ (Eq. 10, d_1+ = 0.6) and the B^ budget "
                                "max(0, 1 - a_F^(n-1) (a_f + a_b)) at (theta_d, n)",
                                {theta_full, count}, rgb_channels({"a_F_n", "A_1plus", "budget"})));

    tbb::parallel_for(0, options.theta_samples, [&](int x) {
        const std::array<glm::dvec3, 3> a = fiber.lobe_attenuation(theta_outgoing.at(x));
        for (int p = 0; p < 3; ++p) put(tables[0], x, 0, 3 * p, a[p]);
        const double theta_d = theta_full.at(x);
        const DualScatteringSample s = per_hair.sample(theta_d);
        const std::array<glm::dvec3, 8> terms{s.a_f, s.a_b, s.A_1, s.A_3, s.delta_b, s.sigma_b,
                                              per_hair.azimuthal_variance(theta_d), s.beta_f * s.beta_f};
        for (size_t t = 0; t < terms.size(); ++t) put(tables[1], x, 0, 3 * t, terms[t]);
        for (int y = 0; y < count.samples; ++y) {
            const double n = count.at(y);
            put(tables[2], x, y, 0, glm::pow(s.a_f, glm::dvec3(n - 1.0)));
            put(tables[2], x, y, 3, side_scatter_series(s.a_f, s.a_b, n));
            put(tables[2], x, y, 6, back_lobe_budget(s, n));
        }
    });
    return tables;
}

namespace {

// A Table2d (axis 0 slow) as a BakedTable (axes[0] along the width, the fast axis).
BakedTable baked_from_table2d(std::string name, std::string equation, const Table2d& t, BakeAxis slow, BakeAxis fast,
                              std::vector<std::string> channels) {
    slow.samples = t.size0;
    slow.begin = t.begin0;
    slow.end = t.end0;
    slow.log_scale = t.log_axis0;
    fast.samples = t.size1;
    fast.begin = t.begin1;
    fast.end = t.end1;
    BakedTable table = make_table(std::move(name), std::move(equation), {fast, slow}, std::move(channels));
    std::copy(t.values.begin(), t.values.end(), table.values.begin());
    return table;
}

}  // namespace

std::vector<BakedTable> bake_circular_gaussian(const CircularGaussianTables& tables) {
    std::vector<BakedTable> baked;
    baked.push_back(baked_from_table2d(
        "xu_cosine", "C_k(lambda', phi) = integral of g^c(x; 0, lambda') |cos((phi - x) / 2)|^k dx, k = 0..6 "
        "(Xu et al. 2011, Eq. 14)",
        tables.cosine, {"lambda", 0, 0, 2}, {"phi", 0, 0, 2}, {"C0", "C1", "C2", "C3", "C4", "C5", "C6"}));
    baked.push_back(baked_from_table2d(
        "xu_h_tt", "H_k^TT(eta', theta_d) = integral of (1 - F)^2 h^k dh, k = 0, 2, 4 (Xu et al. 2011, Eq. 19)",
        tables.h_tt, {"eta", 0, 0, 2}, {"theta_d", 0, 0, 2}, {"H0", "H2", "H4"}));
    baked.push_back(baked_from_table2d(
        "xu_h_trt", "H_k^TRT(eta', theta_d) = integral of (1 - F)^2 F h^k dh, k = 0, 2, 4 (Xu et al. 2011, Eq. 23)",
        tables.h_trt, {"eta", 0, 0, 2}, {"theta_d", 0, 0, 2}, {"H0", "H2", "H4"}));
    return baked;
}

}  // namespace hairlod::bcsdf
