#pragma once
// Single scattering of the Marschner fibre under SRBF lights with the circular Gaussian representation
// (Xu et al. 2011, circular-gaussian-hair-env-lighting.txt, Sec. 3 Eq. 2 and Sec. 4.2, Eq. 11-14).
#include <array>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "hairlod/bcsdf/circular_gaussian.h"
#include "hairlod/bcsdf/marschner.h"

namespace hairlod::bcsdf {

// Xu et al. 2011, Sec. 3: one SRBF light L_j G(w; w_j, lambda_j), G = exp(2 (w . w_j - 1) / lambda_j^2).
struct SrbfLight {
    glm::dvec3 direction{0.0, 1.0, 0.0};  // w_j (normalised on use)
    double lambda = 0.5;                  // bandwidth lambda_j > 0
    glm::dvec3 coefficient{1.0};          // L_j (RGB)
};

double srbf(const glm::dvec3& w, const glm::dvec3& centre, double lambda);

// Sec. 4.2.2: the m + 1 sample positions of the linear quadrature: -pi/2, pi/2 and m - 1 samples spread
// uniformly over mu -+ (m - 2) lambda / 2 (clamped inside), lambda = sqrt(2 variance) the paper's
// Gaussian bandwidth; sorted.
std::vector<double> linear_quadrature_nodes(double mu, double variance, int m);

// The integral over [nodes.front(), nodes.back()] of the normal density N(x; mu, variance) times the
// function linear between (nodes[s], values[s]), in closed form (erf).
glm::dvec3 linear_quadrature(std::span<const double> nodes, std::span<const glm::dvec3> values, double mu,
                             double variance);

// The circular Gaussian (1D) representation of a MarschnerBcsdf: the "circular Gaussian" tier.
class CircularGaussianMarschner final : public FiberBcsdf {
public:
    // m >= 2 is the linear quadrature's sample count minus one (4 in the paper).
    CircularGaussianMarschner(const MarschnerBcsdf& marschner, std::shared_ptr<const CircularGaussianTables> tables,
                              int m = 4);

    // Xu et al. 2011, Eq. 13: N_R ~ sum_k C_k(theta_d, eta) |cos(phi / 2)|^k; C_0 = 0 and C_(k+1) = f_k
    // cos^k(theta_d) / 4 with f_k the least-squares degree-5 fit of the Fresnel factor F(y, eta) on [0, 1].
    std::array<double, 7> r_coefficients(double theta_d) const;

    // S of the representation per lobe (R, TT, TRT): Marschner's M_t / cos^2(theta_d) (divided by
    // max(1, E(theta_o)) like the model) with N_R of Xu 2011 Eq. 13 and the N_TT, N_TRT fits of Eq. 16-23.
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    std::span<const LongitudinalLobe> lobe_shapes() const override { return marschner_.lobe_shapes(); }
    std::string_view name() const override { return "marschner_cg"; }

    // Xu 2011 Eq. 11-14: integral of G_j(w_i) S(w_i, w_o) cos(theta_i) dw_i (times L_j), with g^c(theta_i) ~ the
    // Gaussian exp(-(theta_i - theta_j)^2 / lambda^2) folded into M_t and the rest by linear quadrature.
    glm::dvec3 single_scattering(const SrbfLight& light, const glm::dvec3& wo) const;

    // Xu 2011 Eq. 2: the sum of single_scattering over `lights` at each of `views` (in parallel over views).
    std::vector<glm::dvec3> single_scattering(std::span<const SrbfLight> lights, std::span<const glm::dvec3> views) const;

    const MarschnerBcsdf& marschner() const { return marschner_; }
    const CircularGaussianTables& tables() const { return *tables_; }
    int quadrature_order() const { return m_; }

    // The azimuthal part of lobe p convolved with g^c(.; 0, lambda_prime) (Xu 2011 Eq. 12), or N_p itself
    // when lambda_prime = 0.
    glm::dvec3 azimuthal(int p, double phi, double theta_d, double eta, double lambda_prime) const;

private:

    MarschnerBcsdf marschner_;
    std::shared_ptr<const CircularGaussianTables> tables_;
    int m_;
    std::array<double, 6> fresnel_fit_{};
};

}  // namespace hairlod::bcsdf
