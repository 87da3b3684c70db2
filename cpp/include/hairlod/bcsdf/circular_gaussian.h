#pragma once
// Circular Gaussians and the 1D representation of Marschner's azimuthal functions (Xu et al. 2011,
// circular-gaussian-hair-env-lighting.txt, Sec. 4.2 and 5): g^c, its exact integrals, the N_TT and
// N_TRT fits of Xu 2011 Eq. 16-23, the precomputed tables C_k (Eq. 14) and H_k^TT, H_k^TRT (Eq. 19, 23).
#include <array>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

namespace hairlod::bcsdf {

class MarschnerBcsdf;

// Xu et al. 2011, Table 1 / Eq. 11: g^c(x; mu, lambda) = exp(2 (cos(x - mu) - 1) / lambda^2), peak 1.
double circular_gaussian(double x, double mu, double lambda);

// Integral of g^c over one period: 2 pi e^-kappa I_0(kappa), kappa = 2 / lambda^2 (the paper's
// approximation sqrt(pi) lambda, Sec. 4.2.3, is its small-lambda limit).
double circular_gaussian_integral(double lambda);

// The bandwidth lambda whose g^c integrates to `integral` in (0, 2 pi) (clamped to [1e-9, 1e4]).
double circular_gaussian_bandwidth(double integral);

// Integral over one period of g^c(x; mu_1, lambda_1) g^c(x; mu_2, lambda_2), exact: the product is a
// circular Gaussian of concentration |kappa_1 e^(i mu_1) + kappa_2 e^(i mu_2)| (Xu et al. 2011, Sec. 4.2.3).
double circular_gaussian_product_integral(double mu_1, double lambda_1, double mu_2, double lambda_2);

// b g^c(phi; mu, lambda) per colour channel (the bandwidths differ per channel through absorption).
struct CircularGaussianLobe {
    glm::dvec3 weight{0.0};
    double mu = 0.0;
    glm::dvec3 lambda{1.0};
};

// A sum of up to three lobes approximating one azimuthal function N_t(phi).
struct AzimuthalFit {
    std::array<CircularGaussianLobe, 3> lobes{};
    int count = 0;
    glm::dvec3 eval(double phi) const;
    // Integral of g^c(x; 0, lambda_j') N_t(phi - x) over x (Xu 2011 Eq. 12), in closed form.
    glm::dvec3 convolve(double phi, double lambda_j) const;
};

// Xu et al. 2011, Eq. 18 and 22: the 4th-order Taylor coefficients in h of the absorption along the
// internal chords, T^passes = exp(-passes sigma_a 2 cos(gamma_t) / cos(theta_t)) (attenuation.h),
// with cos(gamma_t) = sqrt(1 - h^2 / eta'^2): coefficients of h^0, h^2, h^4.
std::array<glm::dvec3, 3> absorption_taylor(double eta, const glm::dvec3& sigma_a, double theta_d, int passes);

// A 2D table sampled on a regular grid (axis 0 slow, axis 1 fast) with bilinear lookup (clamped).
struct Table2d {
    double begin0 = 0.0, end0 = 1.0, begin1 = 0.0, end1 = 1.0;
    int size0 = 0, size1 = 0, channels = 1;
    bool log_axis0 = false;  // axis 0 sampled uniformly in log(x)
    std::vector<double> values;  // size0 * size1 * channels
    void lookup(double x0, double x1, double* out) const;
};

// Xu et al. 2011, Sec. 5: the global tables, computed once (in parallel) at the given resolutions.
struct CircularGaussianTables {
    // C_k(lambda', phi), k = 0..6 (channels), lambda' log-uniform in [1e-3, 10], phi in [0, pi] (Xu 2011 Eq. 14).
    Table2d cosine;
    // H_k^TT and H_k^TRT, k = 0, 2, 4 (channels), over eta log-uniform in [1, 10] and theta_d in [0, pi/2].
    Table2d h_tt, h_trt;
};
CircularGaussianTables circular_gaussian_tables(int lambda_samples = 128, int phi_samples = 64,
                                                int eta_samples = 128, int theta_samples = 64);

// The tables at the paper's resolutions, computed once per process on first use (about 0.3 s).
std::shared_ptr<const CircularGaussianTables> default_circular_gaussian_tables();

// Xu et al. 2011, Eq. 14 integrand's definition, by adaptive quadrature (the tables' ground truth).
double cosine_gaussian_integral(int k, double lambda, double phi);
// Xu 2011 Eq. 19 and 23: H_k^TT = integral of (1 - F)^2 h^k dh, H_k^TRT = integral of (1 - F)^2 F h^k dh.
std::array<double, 3> h_integrals(double eta, double theta_d, bool trt);

// Xu 2011 Eq. 16-17 (TT) and Eq. 20-23 (TRT, three lobes below eta' = 2, one above, blended over
// [2, 2 + Delta eta'] as in the paper) for `marschner` at theta_d with index eta (eta* for TRT).
AzimuthalFit fit_tt(const MarschnerBcsdf& marschner, const CircularGaussianTables& tables, double theta_d, double eta);
AzimuthalFit fit_trt(const MarschnerBcsdf& marschner, const CircularGaussianTables& tables, double theta_d,
                     double eta);

}  // namespace hairlod::bcsdf
