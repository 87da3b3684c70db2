#include "hairlod/bcsdf/circular_gaussian.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/common.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/bcsdf/marschner.h"
#include "hairlod/bcsdf/quadrature.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kCosinePowers = 7;

// The seven integrands of C_k at once, so that one adaptive quadrature fills a table cell.
struct CosinePowers {
    std::array<double, kCosinePowers> v{};
    CosinePowers& operator+=(const CosinePowers& o) {
        for (int k = 0; k < kCosinePowers; ++k) v[k] += o.v[k];
        return *this;
    }
    friend CosinePowers operator+(CosinePowers a, const CosinePowers& b) { return a += b; }
    friend CosinePowers operator-(CosinePowers a, const CosinePowers& b) {
        for (int k = 0; k < kCosinePowers; ++k) a.v[k] -= b.v[k];
        return a;
    }
    friend CosinePowers operator*(double w, CosinePowers a) {
        for (double& x : a.v) x *= w;
        return a;
    }
};
double magnitude(const CosinePowers& p) {
    double m = 0.0;
    for (double x : p.v) m = std::max(m, std::abs(x));
    return m;
}

double concentration(double lambda) { return 2.0 / (lambda * lambda); }

// Integral over x in [-pi, pi] of f(x) g^c(x; 0, lambda): split where the lobe lives so that the
// adaptive rule sees narrow lobes (lambda = 1e-3) however wide the interval.
template <typename F>
auto integrate_against_lobe(F&& f, double lambda, const QuadratureTolerance& tolerance) {
    const auto weighted = [&](double x) { return circular_gaussian(x, 0.0, lambda) * f(x); };
    const double w = std::min(kPi, 12.0 * lambda);
    auto sum = integrate_adaptive(weighted, -w, 0.0, tolerance) + integrate_adaptive(weighted, 0.0, w, tolerance);
    if (w < kPi)
        sum += integrate_adaptive(weighted, -kPi, -w, tolerance) + integrate_adaptive(weighted, w, kPi, tolerance);
    return sum;
}

double smoothstep(double edge0, double edge1, double x) {
    const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

}  // namespace

double circular_gaussian(double x, double mu, double lambda) {
    return std::exp((std::cos(x - mu) - 1.0) * concentration(lambda));
}

double circular_gaussian_integral(double lambda) {
    return 2.0 * kPi * std::exp(log_scaled_bessel_i0(concentration(lambda)));
}

double circular_gaussian_bandwidth(double integral) {
    // The integral grows monotonically from 0 to 2 pi with lambda: bisection in log(lambda).
    double lo = std::log(1e-9), hi = std::log(1e4);
    if (!(integral > circular_gaussian_integral(std::exp(lo)))) return std::exp(lo);
    if (integral >= circular_gaussian_integral(std::exp(hi))) return std::exp(hi);
    for (int iteration = 0; iteration < 64; ++iteration) {
        const double mid = 0.5 * (lo + hi);
        (circular_gaussian_integral(std::exp(mid)) < integral ? lo : hi) = mid;
    }
    return std::exp(0.5 * (lo + hi));
}

double circular_gaussian_product_integral(double mu_1, double lambda_1, double mu_2, double lambda_2) {
    const double kappa_1 = concentration(lambda_1), kappa_2 = concentration(lambda_2);
    const double sin_half = std::sin(0.5 * (mu_1 - mu_2));
    const double kappa_sum = kappa_1 + kappa_2;
    // |kappa_1 e^(i mu_1) + kappa_2 e^(i mu_2)|^2 = (kappa_1 + kappa_2)^2 - 4 kappa_1 kappa_2 sin^2(delta / 2).
    const double defect = 4.0 * kappa_1 * kappa_2 * sin_half * sin_half;
    const double kappa = std::sqrt(std::max(0.0, kappa_sum * kappa_sum - defect));
    // kappa - kappa_1 - kappa_2 without cancellation.
    return 2.0 * kPi * std::exp(log_scaled_bessel_i0(kappa) - defect / (kappa + kappa_sum));
}

glm::dvec3 AzimuthalFit::eval(double phi) const {
    glm::dvec3 sum(0.0);
    for (int l = 0; l < count; ++l)
        for (int c = 0; c < 3; ++c)
            sum[c] += lobes[l].weight[c] * circular_gaussian(phi, lobes[l].mu, lobes[l].lambda[c]);
    return sum;
}

glm::dvec3 AzimuthalFit::convolve(double phi, double lambda_j) const {
    // g^c(phi - x; mu, lambda) = g^c(x; phi - mu, lambda).
    glm::dvec3 sum(0.0);
    for (int l = 0; l < count; ++l)
        for (int c = 0; c < 3; ++c)
            sum[c] += lobes[l].weight[c] *
                      circular_gaussian_product_integral(0.0, lambda_j, phi - lobes[l].mu, lobes[l].lambda[c]);
    return sum;
}

std::array<glm::dvec3, 3> absorption_taylor(double eta, const glm::dvec3& sigma_a, double theta_d, int passes) {
    // 2 cos(gamma_t) = 2 - u - u^2/4 + O(u^3), u = h^2 / eta'^2, so with s = passes sigma_a / cos(theta_t):
    // T = e^(-2 s) (1 + s u + (s^2/2 + s/4) u^2) + O(h^6).
    const double sin_theta_t = std::sin(theta_d) / eta;
    const double cos_theta_t = std::sqrt(std::max(1e-12, 1.0 - sin_theta_t * sin_theta_t));
    const double eta_prime = bravais_index(eta, std::sin(theta_d), std::max(std::cos(theta_d), kMinCos));
    const double inv_eta2 = 1.0 / (eta_prime * eta_prime);
    std::array<glm::dvec3, 3> a;
    for (int c = 0; c < 3; ++c) {
        const double s = passes * sigma_a[c] / cos_theta_t;
        const double base = std::exp(-2.0 * s);
        a[0][c] = base;
        a[1][c] = base * s * inv_eta2;
        a[2][c] = base * (0.5 * s * s + 0.25 * s) * inv_eta2 * inv_eta2;
    }
    return a;
}

void Table2d::lookup(double x0, double x1, double* out) const {
    const double u0 = log_axis0 ? (std::log(x0) - std::log(begin0)) / (std::log(end0) - std::log(begin0))
                                : (x0 - begin0) / (end0 - begin0);
    const double u1 = (x1 - begin1) / (end1 - begin1);
    const double f0 = std::clamp(u0, 0.0, 1.0) * (size0 - 1), f1 = std::clamp(u1, 0.0, 1.0) * (size1 - 1);
    const int i0 = std::min(static_cast<int>(f0), size0 - 2), i1 = std::min(static_cast<int>(f1), size1 - 2);
    const double t0 = f0 - i0, t1 = f1 - i1;
    const auto at = [&](int a, int b, int c) { return values[(static_cast<size_t>(a) * size1 + b) * channels + c]; };
    for (int c = 0; c < channels; ++c)
        out[c] = (1.0 - t0) * ((1.0 - t1) * at(i0, i1, c) + t1 * at(i0, i1 + 1, c)) +
                 t0 * ((1.0 - t1) * at(i0 + 1, i1, c) + t1 * at(i0 + 1, i1 + 1, c));
}

double cosine_gaussian_integral(int k, double lambda, double phi) {
    if (k < 0 || k >= kCosinePowers) throw Error("cosine power k must be in [0, 6], got " + std::to_string(k));
    return integrate_against_lobe([&](double x) { return std::pow(std::abs(std::cos(0.5 * (phi - x))), k); },
                                  lambda, {1e-13, 1e-10, 40});
}

std::array<double, 3> h_integrals(double eta, double theta_d, bool trt) {
    const double cos_theta = std::cos(theta_d);
    // In gamma = asin(h) the integrand is smooth up to the rim (as mean_fiber_attenuation).
    const glm::dvec3 sum = integrate_gauss_legendre(
        [&](double gamma) {
            const double h = std::sin(gamma), cos_gamma = std::cos(gamma);
            const double f = fresnel_dielectric(cos_theta * cos_gamma, eta);
            const double weight = (1.0 - f) * (1.0 - f) * (trt ? f : 1.0) * cos_gamma;
            const double h2 = h * h;
            return weight * glm::dvec3(1.0, h2, h2 * h2);
        },
        -0.5 * kPi, 0.5 * kPi, 16);
    return {sum.x, sum.y, sum.z};
}

CircularGaussianTables circular_gaussian_tables(int lambda_samples, int phi_samples, int eta_samples,
                                                int theta_samples) {
    for (int n : {lambda_samples, phi_samples, eta_samples, theta_samples})
        if (n < 2) throw Error("circular Gaussian table resolutions must be >= 2, got " + std::to_string(n));
    CircularGaussianTables tables;
    tables.cosine = {1e-3, 10.0, 0.0, kPi, lambda_samples, phi_samples, kCosinePowers, true, {}};
    tables.cosine.values.resize(static_cast<size_t>(lambda_samples) * phi_samples * kCosinePowers);
    tbb::parallel_for(0, lambda_samples * phi_samples, [&](int cell) {
        const int a = cell / phi_samples, b = cell % phi_samples;
        const double lambda = std::exp(std::log(1e-3) + (std::log(10.0) - std::log(1e-3)) * a / (lambda_samples - 1));
        const double phi = kPi * b / (phi_samples - 1);
        const CosinePowers sum = integrate_against_lobe(
            [&](double x) {
                CosinePowers p;
                const double c = std::abs(std::cos(0.5 * (phi - x)));
                double power = 1.0;
                for (int k = 0; k < kCosinePowers; ++k, power *= c) p.v[k] = power;
                return p;
            },
            lambda, {1e-12, 1e-9, 40});
        std::copy(sum.v.begin(), sum.v.end(), tables.cosine.values.begin() + static_cast<size_t>(cell) * kCosinePowers);
    });
    for (bool trt : {false, true}) {
        Table2d& table = trt ? tables.h_trt : tables.h_tt;
        table = {1.0, 10.0, 0.0, 0.5 * kPi, eta_samples, theta_samples, 3, true, {}};
        table.values.resize(static_cast<size_t>(eta_samples) * theta_samples * 3);
        tbb::parallel_for(0, eta_samples * theta_samples, [&](int cell) {
            const int a = cell / theta_samples, b = cell % theta_samples;
            const double eta = std::exp(std::log(10.0) * a / (eta_samples - 1));
            const double theta_d = 0.5 * kPi * b / (theta_samples - 1);
            const std::array<double, 3> h = h_integrals(eta, theta_d, trt);
            std::copy(h.begin(), h.end(), table.values.begin() + static_cast<size_t>(cell) * 3);
        });
    }
    return tables;
}

std::shared_ptr<const CircularGaussianTables> default_circular_gaussian_tables() {
    static const auto tables = std::make_shared<const CircularGaussianTables>(circular_gaussian_tables());
    return tables;
}

namespace {

// Xu et al. 2011, Eq. 19 / 23: integral of N_t over phi = 1/2 sum_k taylor_k H_k(eta, theta_d).
glm::dvec3 azimuthal_energy(const MarschnerBcsdf& marschner, const Table2d& h_table, double theta_d, double eta,
                            int passes) {
    const std::array<glm::dvec3, 3> taylor = absorption_taylor(eta, marschner.params().sigma_a, theta_d, passes);
    double h[3];
    h_table.lookup(eta, std::abs(theta_d), h);
    return 0.5 * (taylor[0] * h[0] + taylor[1] * h[1] + taylor[2] * h[2]);
}

// A lobe of energy `energy` and peak `peak` (Xu 2011 Eq. 17): lambda from the exact integral of g^c.
CircularGaussianLobe energy_preserving_lobe(const glm::dvec3& energy, const glm::dvec3& peak, double mu) {
    CircularGaussianLobe lobe;
    lobe.mu = mu;
    for (int c = 0; c < 3; ++c) {
        if (!(peak[c] > 0.0 && energy[c] > 0.0)) continue;
        lobe.lambda[c] = circular_gaussian_bandwidth(energy[c] / peak[c]);
        lobe.weight[c] = energy[c] / circular_gaussian_integral(lobe.lambda[c]);
    }
    return lobe;
}

}  // namespace

AzimuthalFit fit_tt(const MarschnerBcsdf& marschner, const CircularGaussianTables& tables, double theta_d, double eta) {
    // Xu 2011 Eq. 16-17: b_tt = N_TT(pi), lambda_tt preserves the energy of Eq. 19.
    AzimuthalFit fit;
    fit.count = 1;
    fit.lobes[0] = energy_preserving_lobe(azimuthal_energy(marschner, tables.h_tt, theta_d, eta, 1),
                                          marschner.root_azimuthal(1, kPi, theta_d, eta), kPi);
    return fit;
}

AzimuthalFit fit_trt(const MarschnerBcsdf& marschner, const CircularGaussianTables& tables, double theta_d,
                     double eta) {
    const double eta_prime = bravais_index(eta, std::sin(theta_d), std::max(std::cos(theta_d), kMinCos));
    const glm::dvec3 energy = azimuthal_energy(marschner, tables.h_trt, theta_d, eta, 2);
    const double w_c = marschner.caustic().width;
    const double i_c = circular_gaussian_integral(w_c);
    AzimuthalFit fit;
    if (eta_prime < 2.0) {
        // Xu 2011 Eq. 20-21: caustic lobes of width w_c at +-phi*, phi* = phi(h*), h* = sqrt((4 - eta'^2) / 3), and
        // a residue lobe of bandwidth phi* at 0; b_1 preserves the energy (Xu 2011 Eq. 23).
        const double h_star = std::sqrt((4.0 - eta_prime * eta_prime) / 3.0);
        const double phi_star =
            std::abs(wrap_angle(4.0 * std::asin(h_star / eta_prime) - 2.0 * std::asin(h_star) + 2.0 * kPi));
        const double residue = 1.0 - circular_gaussian(0.0, phi_star, w_c);
        const glm::dvec3 b_2 = marschner.root_azimuthal(2, 0.0, theta_d, eta) * (residue * residue);
        const double i_2 = phi_star > 0.0 ? circular_gaussian_integral(phi_star) : 0.0;
        const glm::dvec3 b_1 = glm::max(glm::dvec3(0.0), (energy - b_2 * i_2) / (2.0 * i_c));
        fit.count = phi_star > 0.0 ? 3 : 1;
        fit.lobes[0] = {b_1, phi_star, glm::dvec3(w_c)};
        fit.lobes[1] = {b_1, -phi_star, glm::dvec3(w_c)};
        fit.lobes[2] = {b_2, 0.0, glm::dvec3(std::max(phi_star, 1e-9))};
        if (fit.count == 1) fit.lobes[0].weight = energy / i_c;
        return fit;
    }
    // Above eta' = 2 one lobe b_3 g^c(phi; 0, lambda_3); its bandwidth blends from w_c over [2, 2 + Delta eta']
    // and the weight keeps the energy (Sec. 4.2.4).
    const CircularGaussianLobe single = energy_preserving_lobe(energy, marschner.root_azimuthal(2, 0.0, theta_d, eta), 0.0);
    const double t = smoothstep(2.0, 2.0 + marschner.caustic().fade_range, eta_prime);
    fit.count = 1;
    fit.lobes[0].mu = 0.0;
    for (int c = 0; c < 3; ++c) {
        fit.lobes[0].lambda[c] = (1.0 - t) * w_c + t * single.lambda[c];
        fit.lobes[0].weight[c] = energy[c] / circular_gaussian_integral(fit.lobes[0].lambda[c]);
    }
    return fit;
}

}  // namespace hairlod::bcsdf
