#include "hairlod/bcsdf/aggregated.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;

void require_positive(const char* name, double value) {
    if (!(std::isfinite(value) && value > 0.0))
        throw Error(std::string(name) + " must be finite and > 0, got " + std::to_string(value));
}

// Linear interpolation of a table sampled uniformly over theta_d in [-pi/2, pi/2].
template <typename Table, typename Get>
auto interpolate(const Table& table, double theta_d, Get&& get) {
    const int count = static_cast<int>(table.size());
    const double x = (std::clamp(theta_d, -0.5 * kPi, 0.5 * kPi) + 0.5 * kPi) / kPi * (count - 1);
    const int k = std::min(static_cast<int>(x), count - 2);
    const double t = x - k;
    return (1.0 - t) * get(table[k]) + t * get(table[k + 1]);
}

void validate_cluster(const ClusterState& cluster) {
    if (!(std::isfinite(cluster.hair_count) && cluster.hair_count >= 1.0))
        throw Error("hair_count must be finite and >= 1, got " + std::to_string(cluster.hair_count));
    if (!(cluster.density > 0.0 && cluster.density <= 1.0))
        throw Error("density must be in (0, 1], got " + std::to_string(cluster.density));
    if (!(std::isfinite(cluster.light_crossings) && cluster.light_crossings >= 0.0))
        throw Error("light_crossings must be finite and >= 0, got " + std::to_string(cluster.light_crossings));
}

// The arguments of a ray crossing a thick hair (hairs_crossed, hair_hit_probability).
void validate_crossing(double density, double ray_length, double hair_total, double major_axis, double minor_axis) {
    require_positive("density", density);
    require_positive("hair_total", hair_total);
    require_positive("major_axis", major_axis);
    require_positive("minor_axis", minor_axis);
    if (!(std::isfinite(ray_length) && ray_length >= 0.0))
        throw Error("ray_length must be finite and >= 0, got " + std::to_string(ray_length));
}

}  // namespace

double cluster_density(double hair_total, double hair_radius, double major_axis, double minor_axis) {
    require_positive("hair_total", hair_total);
    require_positive("hair_radius", hair_radius);
    require_positive("major_axis", major_axis);
    require_positive("minor_axis", minor_axis);
    return std::min(1.0, hair_total * hair_radius * hair_radius / (major_axis * minor_axis));
}

double hairs_crossed(double density, double ray_length, double hair_total, double major_axis, double minor_axis) {
    validate_crossing(density, ray_length, hair_total, major_axis, minor_axis);
    return std::max(1.0, density * ray_length * std::sqrt(hair_total / (kPi * major_axis * minor_axis)));
}

double max_hairs_crossed(std::span<const float> n_total, std::span<const glm::vec2> radii,
                         std::span<const float> density) {
    if (radii.size() != density.size()) throw Error("max_hairs_crossed: radii and density need one entry per point");
    if (n_total.empty()) return 1.0;
    if (radii.size() % n_total.size() != 0)
        throw Error("max_hairs_crossed: points must be a whole number of control points per hair");
    const size_t per_hair = radii.size() / n_total.size();
    double most = 1.0;
    for (size_t i = 0; i < radii.size(); ++i) {
        const double total = n_total[i / per_hair];
        const double r_a = radii[i].x, r_b = radii[i].y, rho = std::min(1.0, static_cast<double>(density[i]));
        const double n = (r_a > 0.0 && r_b > 0.0 && rho > 0.0 && total > 0.0)
                             ? hairs_crossed(rho, 2.0 * r_a, total, r_a, r_b)
                             : total;
        most = std::max(most, std::min(n, total));
    }
    return most;
}

double expected_hairs_met(double density, double ray_length, double hair_total, double major_axis, double minor_axis) {
    validate_crossing(density, ray_length, hair_total, major_axis, minor_axis);
    // r = sqrt(rho |r_A| |r_B| / n_total) from Sec. 4's rho, so 2 r n_total / (pi |r_A| |r_B|) is this.
    return 2.0 / kPi * ray_length * std::sqrt(density * hair_total / (major_axis * minor_axis));
}

double hair_hit_probability(double density, double ray_length, double hair_total, double major_axis, double minor_axis) {
    return -std::expm1(-expected_hairs_met(density, ray_length, hair_total, major_axis, minor_axis));
}

glm::dvec3 side_scatter_series(const glm::dvec3& a_f, const glm::dvec3& a_b, double hair_count) {
    // sum_{i=1..n} a_F^(2i-1) = a_F (1 - a_F^(2n)) / (1 - a_F^2), n at a_F = 1.
    glm::dvec3 a_1_plus;
    for (int c = 0; c < 3; ++c) {
        const double series =
            a_f[c] < 1.0 ? a_f[c] * (1.0 - std::pow(a_f[c], 2.0 * hair_count)) / (1.0 - a_f[c] * a_f[c]) : hair_count;
        a_1_plus[c] = kSideScatterWeight * a_b[c] * series;
    }
    return a_1_plus;
}

glm::dvec3 back_lobe_budget(const DualScatteringSample& seen, double hair_count) {
    const glm::dvec3 direct = glm::pow(seen.a_f, glm::dvec3(hair_count - 1.0)) * (seen.a_f + seen.a_b);
    return glm::max(glm::dvec3(0.0), 1.0 - direct);
}

DualScatteringSample AggregatedTable::sample(double theta_d) const {
    DualScatteringSample s;
    s.theta_d = theta_d;
    for (glm::dvec3 DualScatteringSample::*field :
         {&DualScatteringSample::a_f, &DualScatteringSample::a_b, &DualScatteringSample::alpha_f,
          &DualScatteringSample::alpha_b, &DualScatteringSample::beta_f, &DualScatteringSample::beta_b,
          &DualScatteringSample::A_1, &DualScatteringSample::A_3, &DualScatteringSample::A_b,
          &DualScatteringSample::delta_b, &DualScatteringSample::sigma_b})
        s.*field = interpolate(samples, theta_d, [&](const DualScatteringSample& t) { return t.*field; });
    return s;
}

glm::dvec3 AggregatedTable::azimuthal_variance(double theta_d) const {
    return interpolate(forward_azimuthal_variance, theta_d, [](const glm::dvec3& v) { return v; });
}

AggregatedTable aggregated_table(const FiberRtdBcsdf& fiber, int samples, double backscatter_density) {
    if (samples < 3) throw Error("an aggregated table needs at least 3 samples, got " + std::to_string(samples));
    AggregatedTable table;
    table.samples.resize(samples);
    table.forward_azimuthal_variance.resize(samples);
    const QuadratureTolerance tolerance{1e-5, 1e-4, 24};
    tbb::parallel_for(0, samples, [&](int k) {
        const double theta_d = -0.5 * kPi + kPi * k / (samples - 1);
        table.samples[k] = dual_scattering(fiber, theta_d, backscatter_density, tolerance);
        // Huang 2025 Eq. 9's sigma_f^2: the forward-scattered energy's variance of phi around pi.
        const glm::dvec3 wo = fiber_frame_direction(theta_d, 0.0);
        const glm::dvec3 moment = integrate_directions(
            [&](const glm::dvec3& wi) {
                const double offset = wrap_angle(fiber_direction(wo).phi - fiber_direction(wi).phi - kPi);
                return offset * offset * fiber.eval(wi, wo);
            },
            0.5 * kPi, 1.5 * kPi, tolerance);
        const glm::dvec3 a_f = table.samples[k].a_f;
        for (int c = 0; c < 3; ++c) table.forward_azimuthal_variance[k][c] = a_f[c] > 0.0 ? moment[c] / a_f[c] : 0.0;
    });
    return table;
}

AggregatedBcsdf::AggregatedBcsdf(const HairParams& params, const ClusterState& cluster,
                                 std::shared_ptr<const AggregatedTable> table, AggregatedFibre fibre)
    : fiber_(params), cluster_(cluster), table_(std::move(table)) {
    validate_cluster(cluster_);
    if (!table_) table_ = std::make_shared<const AggregatedTable>(aggregated_table(fiber_));
    if (fibre == AggregatedFibre::Material) material_.emplace(params);
    const auto shapes = material_ ? material_->lobe_shapes() : fiber_.lobe_shapes();
    // B^ varies with theta_d; its shape at theta_d = 0 (channel mean) stands for it in lobe_shapes().
    const DualScatteringSample normal = table_->sample(0.0);
    const double delta_b = (normal.delta_b.x + normal.delta_b.y + normal.delta_b.z) / 3.0;
    const double sigma_b = (normal.sigma_b.x + normal.sigma_b.y + normal.sigma_b.z) / 3.0;
    lobes_ = {shapes[0], shapes[1], shapes[2], LongitudinalLobe{delta_b, 4.0 * sigma_b * sigma_b}};
}

glm::dvec3 AggregatedBcsdf::shadowing_masking(double phi, const glm::dvec3& a_f) const {
    return shadowing_masking(phi, a_f, cluster_.density);
}

glm::dvec3 AggregatedBcsdf::shadowing_masking(double phi, const glm::dvec3& a_f, double density) {
    if (std::abs(phi) >= 0.5 * kPi) return glm::dvec3(1.0);
    const double open = 1.0 - density;
    const double p_m = open * kMultipleShadowing;                                  // Huang 2025 Eq. 13
    const double p_s = std::clamp(open * (1.0 - std::cos(phi)), 0.0, 1.0 - p_m);  // Huang 2025 Eq. 12
    const double p_n = 1.0 - p_m - p_s;                                            // Huang 2025 Eq. 14
    return p_s * a_f + glm::dvec3(p_n);                                            // Huang 2025 Eq. 15
}

LobeValues AggregatedBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    return lobes_at(wi, wo, cluster_);  // validated at construction
}

LobeValues AggregatedBcsdf::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, const ClusterState& cluster) const {
    validate_cluster(cluster);
    return lobes_at(wi, wo, cluster);
}

LobeValues AggregatedBcsdf::lobes_at(const glm::dvec3& wi, const glm::dvec3& wo, const ClusterState& cluster) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const HalfAngles angles = half_angles(di, dout);
    const DualScatteringSample hair = table_->sample(angles.theta_d);
    const double crossed = cluster.shaded_inside ? cluster.light_crossings : cluster.hair_count - 1.0;

    // Huang 2025 Eq. 7 and 9: R^, TT^, D^ after n - 1 forward scatterings (variances in theta_h, x4 in theta_i).
    // Huang 2025 Eq. 9 as printed widens the longitudinal lobes by the forward *azimuthal* variance sigma_f^2 too;
    // here they widen by dual scattering's longitudinal one, beta_f^2 (Zinke et al. 2008, whose spread Eq. 9
    // accumulates; the renderer's ds method does the same). sigma_f^2 is about 0.4 rad^2 for brown hair,
    // beta_f^2 under 0.01: with sigma_f^2 a thick hair lit from behind spread its transmitted light over
    // every inclination after one crossing and returned 1.8-2x its strands' light, 1.1-1.3x with beta_f^2
    // (`bench thick-hairs`, the artist-made hair).
    RtdSpread spread;
    spread.attenuation = cluster.shaded_inside ? glm::exp(-crossed * (1.0 - glm::min(hair.a_f, glm::dvec3(1.0))))
                                               : glm::pow(hair.a_f, glm::dvec3(crossed));
    const glm::dvec3 sigma_f2 = table_->azimuthal_variance(angles.theta_d);
    const double sigma_f2_mean = (sigma_f2.x + sigma_f2.y + sigma_f2.z) / 3.0;
    const glm::dvec3 beta_f2 = hair.beta_f * hair.beta_f;
    spread.longitudinal_variance = 4.0 * crossed * (beta_f2.x + beta_f2.y + beta_f2.z) / 3.0;
    spread.azimuthal_variance = crossed * sigma_f2_mean;
    LobeValues out;
    if (material_) {
        // The material's TRT and TRRT+ together in D^'s place; B^ takes the fourth.
        out = material_->eval_lobes(wi, wo, spread);
        out.value[2] += out.value[3];
        out.value[3] = glm::dvec3(0.0);
    } else {
        out = fiber_.eval_lobes(wi, wo, spread);
    }
    out.count = 4;

    // Huang 2025 Eq. 10-11: B^ = A_1+ + A_1 + A_3 towards the back hemisphere, with
    // A_1+ = d_1+ a_B sum_{i=1..n} a_F^(2i-1) = d_1+ a_B a_F (1 - a_F^(2n)) / (1 - a_F^2).
    if (std::abs(angles.phi) < 0.5 * kPi) {
        // Shaded inside, the series runs over the strands behind the shaded one (hair_count - 1 of them,
        // a Poisson mean: the closed form takes a fractional count, and none gives no A_1+).
        const glm::dvec3 a_1_plus =
            side_scatter_series(hair.a_f, hair.a_b, cluster.shaded_inside ? cluster.hair_count - 1.0 : cluster.hair_count);
        // Energy bound (decision; Sec. 4 leaves it open): B^ returns light that the cluster's hairs
        // scattered, so it carries at most what the direct lobes leave of the unit budget seen from
        // wo, 1 - a_F^(n-1) (a_f + a_b) at theta_o (a_f + a_b is the fibre's furnace there, and B^'s
        // lobe integrates to at most its attenuation). A lone lossless hair (n = 1) thus gets almost
        // no B^; without the cap the lossless aggregate reached 1.10 at n = 1, theta_o = 0.
        const DualScatteringSample seen = table_->sample(dout.theta);
        // Shaded inside, the direct lobes are those behind the light's crossings (their attenuation there).
        const glm::dvec3 budget =
            cluster.shaded_inside
                ? glm::max(glm::dvec3(0.0), 1.0 - glm::exp(-crossed * (1.0 - glm::min(seen.a_f, glm::dvec3(1.0)))) *
                                                      (seen.a_f + seen.a_b))
                : back_lobe_budget(seen, cluster.hair_count);
        // Shaded inside by a path tracer, the light that the hairs around the thick hair scatter back
        // (A_1 + A_3: dual scattering's backscatter of an unbounded hair volume, Zinke et al. 2008) is
        // carried by the paths it traces between hairs; only A_1+, from the hair's own strands behind the
        // shaded one (which those paths skip), stays in B^.
        const glm::dvec3 surroundings = cluster.shaded_inside ? glm::dvec3(0.0) : hair.A_1 + hair.A_3;
        const glm::dvec3 a_b = glm::min(a_1_plus + surroundings, budget);
        const glm::dvec3 sigma_b2 = hair.sigma_b * hair.sigma_b;
        for (int c = 0; c < 3; ++c) {
            const double m = gaussian_longitudinal(di.theta, dout.theta, hair.delta_b[c],
                                                   std::max(4.0 * sigma_b2[c], 1e-12));
            out.value[3][c] = a_b[c] * m / kPi;
        }
    }

    const glm::dvec3 shadowing = shadowing_masking(angles.phi, hair.a_f, cluster.density);
    for (int p = 0; p < out.count; ++p) out.value[p] *= shadowing;
    return out;
}

}  // namespace hairlod::bcsdf
