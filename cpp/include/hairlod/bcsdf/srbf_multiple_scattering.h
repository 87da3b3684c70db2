#pragma once
// Multiple scattering under SRBF lights with the dual-scattering approximation (Xu et al. 2011,
// circular-gaussian-hair-env-lighting.txt, Sec. 3 Eq. 3-5 and Sec. 4.3, Eq. 27-31; Zinke et al. 2008).
//
// The model (what the fast path approximates and the brute-force reference integrates), per light j:
//   L^D(w_o) = d_f T_f L_j  integral over w_i of L_f(w_i) S^D(w_i, w_o) cos(theta_i) dw_i          (Xu 2011 Eq. 3)
//   L_f(w_i) = integral over w_d of G_j(w_d) psi_f(w_d -> w_i) dw_d,
//   psi_f    = s_f(phi_i - phi_d) N(theta_i; theta_d, sigma_f-bar^2) / cos(theta_d)                 (Xu 2011 Eq. 5)
//   S^D      = S + d_b S_back                                                                       (Xu 2011 Eq. 4)
//   S_back   = A_b(theta_d) s_b(phi) N(theta_i; 2 Delta_b(theta_d) - theta_o, 4 sigma_b^2(theta_d))
//              / cos^2(theta_d)
// with s_f = 1/pi where |phi_i - phi_d| < pi/2 (the light keeps its azimuth), s_b = 1/pi where
// |phi_o - phi_i| < pi/2, N a unit-area Gaussian, theta_d = (theta_o - theta_i) / 2 (Table 1), S the
// Marschner fibre and A_b, Delta_b, sigma_b Zinke's backscattering terms (dual_scattering.h).
//
// Decisions. (1) sigma_f-bar^2 is the variance (rad^2) of the forward spread in theta, Zinke's sum of
// beta_f^2; Xu writes sigma_f = sqrt(lambda^2 + sigma_f-bar^2) in bandwidths (variance = bandwidth^2 / 2),
// so the spread profile here has variance lambda^2 / 2 + sigma_f-bar^2. (2) Delta_b and sigma_b are in the
// theta_h convention of dual_scattering.h, so in theta_i the backscatter lobe has mean 2 Delta_b - theta_o
// and variance 4 sigma_b^2, unit area like this repository's M_t (Xu 2011 Eq. 7 without its factor 2 of
// d theta_h = d theta_i / 2): the local term returns the fraction A_b of what arrives. (3) Xu folds the
// SRBF's power pi lambda^2 into L_j (Xu 2011 Eq. 27 keeps only 1 / cos(theta_j)); here it is explicit, so that
// L_j is the same coefficient single scattering takes. (4) The SRBF's azimuthal width is kept (Xu 2011 Eq. 28
// and 30 drop it): the box s_f is convolved with g^c(phi; phi_j, lambda'_j), which matters for wide lights.
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "hairlod/bcsdf/dual_scattering.h"
#include "hairlod/bcsdf/srbf.h"

namespace hairlod::bcsdf {

// Zinke et al. 2008's forward-scattering density factor d_f (between 0.6 and 0.8).
inline constexpr double kDefaultForwardDensity = 0.7;

// What the light of one SRBF has gone through on its way to the shading point (Xu 2011 Eq. 3 and 5).
struct ForwardScattering {
    glm::dvec3 transmittance{1.0};  // T_f(w_j) in [0, 1]
    double variance = 0.0;          // sigma_f-bar^2(w_j) >= 0, rad^2
};

struct MultipleScatteringRadiance {
    glm::dvec3 global{0.0};  // Sec. 4.3.1: d_f T_f L_j integral L_f S cos(theta_i) dw_i
    glm::dvec3 local{0.0};   // Sec. 4.3.2: the same with d_b S_back
    glm::dvec3 total() const { return global + local; }
};

// The backscattering terms A_b, Delta_b, sigma_b (Zinke et al. 2008, Sec. 4) over theta_d in
// [-pi/2, pi/2] on a uniform grid, with linear interpolation and running sums for the averages of Xu 2011 Eq. 31
// (the paper's 1D summed-area tables, Sec. 5).
class BackscatterTable {
public:
    // `samples` at uniform theta_d from -pi/2 to pi/2 (at least 2), computed with density d_b.
    BackscatterTable(std::span<const DualScatteringSample> samples, double backscatter_density);

    struct Terms {
        glm::dvec3 A_b{0.0}, delta_b{0.0}, sigma_b{0.0};
    };
    Terms at(double theta_d) const;
    // Xu 2011 Eq. 31: the mean of Delta_b and sigma_b over theta_d in [lo, hi] (A_b left zero); at(lo) if lo = hi.
    Terms mean(double lo, double hi) const;
    double backscatter_density() const { return d_b_; }

private:
    // Integral of the interpolated terms from -pi/2 to theta_d.
    Terms cumulative(double theta_d) const;

    std::vector<Terms> nodes_;
    std::vector<Terms> running_;  // cumulative trapezoid sums at the nodes
    double step_ = 0.0;
    double d_b_ = kDefaultBackscatterDensity;
};

// The table from `bcsdf` at `samples` uniform nodes (dual_scattering_table, in parallel).
BackscatterTable backscatter_table(const FiberBcsdf& bcsdf, int samples,
                                   double backscatter_density = kDefaultBackscatterDensity,
                                   const QuadratureTolerance& tolerance = {1e-6, 1e-5, 30});

// Sec. 4.3: the fast path, on the circular Gaussian representation of the fibre.
class SrbfMultipleScattering {
public:
    SrbfMultipleScattering(const CircularGaussianMarschner& fibre, BackscatterTable backscatter,
                           double forward_density = kDefaultForwardDensity);

    // Global (Xu 2011 Eq. 27-28) and local (Eq. 29-31) multiple scattering of one light at `wo`.
    MultipleScatteringRadiance eval(const SrbfLight& light, const glm::dvec3& wo,
                                    const ForwardScattering& forward) const;
    // The sum over `lights` (forward[j] for lights[j]) at each of `views` (in parallel over views).
    std::vector<MultipleScatteringRadiance> eval(std::span<const SrbfLight> lights,
                                                 std::span<const ForwardScattering> forward,
                                                 std::span<const glm::dvec3> views) const;

private:
    // Xu 2011 Eq. 28 generalised: (1/pi) integral over u in [-pi/2, pi/2] of the lobe's Eq. 12 convolution
    // N_t(lambda', delta_phi - u).
    glm::dvec3 global_azimuthal(int p, double delta_phi, double theta_d, double eta, double lambda_prime) const;

    CircularGaussianMarschner fibre_;
    BackscatterTable backscatter_;
    double d_f_;
};

// The brute-force reference of the same model for every view direction and the sum over `lights`
// (forward[j] for lights[j]): the light field L_f on a theta x phi midpoint grid (exact SRBFs, the
// phi window summed, the theta spread integrated cell by cell), then the outgoing integral on the same
// grid with the exact Marschner fibre `fibre` (in parallel over wo).
std::vector<MultipleScatteringRadiance> srbf_multiple_scattering_reference(
    const MarschnerBcsdf& fibre, const BackscatterTable& backscatter, std::span<const SrbfLight> lights,
    std::span<const ForwardScattering> forward, std::span<const glm::dvec3> wo,
    double forward_density = kDefaultForwardDensity, int theta_samples = 256, int phi_samples = 512);

}  // namespace hairlod::bcsdf
