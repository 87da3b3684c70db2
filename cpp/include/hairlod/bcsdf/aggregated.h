#pragma once
// The aggregated BCSDF of a thick hair standing for a cluster of strands (hair-lod-aggregated-bcsdf.txt,
// Huang et al. 2025, Sec. 4, Eq. 6-15), built on the R, TT, D fibre of Eq. 1 (FiberRtdBcsdf):
//   f = S(phi, theta_d) * sum over p in {R^, TT^, D^, B^} of A_p M_p(theta_h) N_p(phi).
//
// Conventions (see FiberRtdBcsdf): theta_d is Marschner's half difference (theta_o - theta_i) / 2,
// which the paper's tables are functions of; variances of Huang 2025 Eq. 9 are in theta_h, so they enter the
// unit-area-in-theta_i lobes multiplied by 4. The per-hair terms a_F, a_B, the forward azimuthal
// variance sigma_f^2, A_1, A_3, Delta_b and sigma_b are tabulated over theta_d from the single fibre by
// numerical integration (dual_scattering.h) when the model is built.
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/dual_scattering.h"
#include "hairlod/bcsdf/fiber_rtd.h"

namespace hairlod::bcsdf {

// Paper constants: d_1+ of Huang 2025 Eq. 10 and c_m of Eq. 13.
inline constexpr double kSideScatterWeight = 0.6;
inline constexpr double kMultipleShadowing = 0.2;

// The smallest rho the renderer passes on (rho must be positive). Real hair is sparse: 57 strands of
// radius 1e-4 in a cluster a few centimetres across have rho ~ 1e-5, and any larger floor makes
// such thick hairs block more rays than their strands (lambda grows with sqrt(rho)).
inline constexpr double kMinClusterDensity = 1e-12;

// Where the shading point is inside the thick hair (Sec. 4, "Estimation of hair number n").
struct ClusterState {
    double hair_count = 1.0;  // n >= 1: hairs the incident ray crossed, the shaded one included
    double density = 1.0;     // rho in (0, 1]: area fraction of the cross-section covered by hairs
    // A path tracer that shades the first strand its ray meets inside the thick hair and traces light
    // between hairs (render/integrator.cpp) knows how many of the hair's strands the light crossed to
    // reach it: `light_crossings`, a Poisson mean k. Sec. 4 takes n from the ray that carries the
    // incident radiance; with k known, R^, TT^ and D^ have the attenuation of Huang 2025 Eq. 7 averaged over the
    // Poisson count, E[a_F^k] = exp(-k (1 - a_F)), and the spread of Huang 2025 Eq. 9 with n - 1 = k; hair_count
    // then counts the shaded strand and the strands behind it, and Huang 2025 Eq. 10's A_1+ series runs over the
    // hair_count - 1 strands behind (none behind, no A_1+); B^ keeps only A_1+ (the backscatter of the
    // hairs around, A_1 + A_3, is on the traced paths).
    bool shaded_inside = false;
    double light_crossings = 0.0;
};

// Sec. 4: rho = n_total r^2 / (|r_A| |r_B|) for n_total hairs of radius r in an ellipse of semi-axes
// r_A, r_B (clamped to 1); throws Error naming the bad argument.
double cluster_density(double hair_total, double hair_radius, double major_axis, double minor_axis);

// Sec. 4: n = rho l sqrt(n_total / (pi |r_A| |r_B|)) hairs along a ray of length l, at least 1.
double hairs_crossed(double density, double ray_length, double hair_total, double major_axis, double minor_axis);

// The most hairs a ray crosses in a level of thick hairs (Sec. 4 and 5.2): hairs_crossed along the
// longest chord l = 2 r_A of each control point's ellipse, rho clamped to 1 and n never above the
// hair's n_total; at least 1. n_total holds one count per hair; radii (r_A, r_B) and density one entry
// per control point, n_total.size() x control points in all. Points with an empty ellipse or no
// density cross nothing more than the hair itself. The largest n the aggregated tables must cover.
double max_hairs_crossed(std::span<const float> n_total, std::span<const glm::vec2> radii,
                         std::span<const float> density);

// The probability that a ray of length l through the cross-section meets at least one of its hairs:
// 1 - exp(-lambda), the hairs taken as n_total discs of radius r placed independently and uniformly in
// the ellipse (a Poisson count), each blocking a width 2 r, so lambda = 2 r n_total l / (pi |r_A| |r_B|)
// with r = sqrt(rho |r_A| |r_B| / n_total) from Sec. 4's rho. Sec. 4 draws the thick hair opaque; where
// rho is small (the tips) its gaps let the background and the light through, as the strands do.
double hair_hit_probability(double density, double ray_length, double hair_total, double major_axis, double minor_axis);

// The Poisson mean of hair_hit_probability: lambda = 2 r n_total l / (pi |r_A| |r_B|), the hairs a ray
// of length l (in the cross-section's plane) meets on average. Means over disjoint pieces of one
// path add up.
double expected_hairs_met(double density, double ray_length, double hair_total, double major_axis, double minor_axis);

// Huang 2025 Eq. 10: A_1+ = d_1+ a_B sum_{i=1..n} a_F^(2i-1) in closed form (n need not be an integer).
glm::dvec3 side_scatter_series(const glm::dvec3& a_f, const glm::dvec3& a_b, double hair_count);

// The energy budget of B^ seen from an inclination with per-hair terms `seen`:
// max(0, 1 - a_F^(n-1) (a_f + a_b)) (see AggregatedBcsdf::eval_lobes).
glm::dvec3 back_lobe_budget(const DualScatteringSample& seen, double hair_count);

// The per-hair terms of the single fibre over theta_d in [-pi/2, pi/2] (uniform samples).
struct AggregatedTable {
    std::vector<DualScatteringSample> samples;
    std::vector<glm::dvec3> forward_azimuthal_variance;  // sigma_f^2 of Huang 2025 Eq. 9, around phi = pi
    // Linear interpolation at theta_d.
    DualScatteringSample sample(double theta_d) const;
    glm::dvec3 azimuthal_variance(double theta_d) const;
};

// Builds the table of `fiber` with `samples` >= 3 inclinations (in parallel).
AggregatedTable aggregated_table(const FiberRtdBcsdf& fiber, int samples = 33,
                                 double backscatter_density = kDefaultBackscatterDensity);

// The fibre whose lobes the aggregated BCSDF attenuates and widens (Huang 2025 Eq. 7 and 9): the R, TT, D
// fibre of Huang 2025 Eq. 1 (the renderer's thick hairs, the baked tables), or the material's own Chiang fibre in the
// far field (ChiangBcsdf, its TRT and TRRT+ in D^'s place), as the viewport preview shades strands and
// thick hairs (docs/preview.md, "The material's fibre in the preview"). The per-hair terms (a_F, a_B,
// A_1, A_3, sigma_f^2) are the R, TT, D fibre's either way: both have the material's albedo at every theta.
enum class AggregatedFibre { Rtd, Material };

class AggregatedBcsdf final : public FiberBcsdf {
public:
    // Validates params and cluster (hair_count >= 1, density in (0, 1]); builds the table unless given.
    AggregatedBcsdf(const HairParams& params, const ClusterState& cluster,
                    std::shared_ptr<const AggregatedTable> table = nullptr, AggregatedFibre fibre = AggregatedFibre::Rtd);

    // Lobes R^, TT^, D^, B^, each multiplied by the shadowing-masking S(phi, theta_d) of Huang 2025 Eq. 15; B^'s
    // attenuation is capped by the energy budget 1 - a_F^(n-1) (a_f + a_b) at theta_o, so the lossless model's
    // white furnace stays <= 1 + 1e-3 for every n >= 1 and rho.
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    // The same at another cluster state (a renderer's n and rho per hit): equal to the model built with
    // `cluster`, without building one (the state enters only Huang 2025 Eq. 7, 9, 10 and 12-15). Throws Error unless
    // hair_count >= 1 and density is in (0, 1].
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, const ClusterState& cluster) const;
    std::span<const LongitudinalLobe> lobe_shapes() const override { return lobes_; }
    std::string_view name() const override { return "aggregated"; }

    // Huang 2025 Eq. 12-15 for |phi| < pi/2 (1 otherwise); the probabilities are clamped to [0, 1].
    glm::dvec3 shadowing_masking(double phi, const glm::dvec3& a_f) const;
    static glm::dvec3 shadowing_masking(double phi, const glm::dvec3& a_f, double density);
    const std::shared_ptr<const AggregatedTable>& table() const { return table_; }
    const FiberRtdBcsdf& fiber() const { return fiber_; }

private:
    LobeValues lobes_at(const glm::dvec3& wi, const glm::dvec3& wo, const ClusterState& cluster) const;

    FiberRtdBcsdf fiber_;
    std::optional<ChiangBcsdf> material_;  // the fibre of AggregatedFibre::Material
    ClusterState cluster_;
    std::shared_ptr<const AggregatedTable> table_;
    std::array<LongitudinalLobe, 4> lobes_;
};

}  // namespace hairlod::bcsdf
