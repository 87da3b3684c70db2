#include "hairlod/bcsdf/srbf.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kFresnelDegree = 5;

// Least-squares polynomial of degree 5 in y of the Fresnel factor F(y, eta) on y in [0, 1] (64
// Chebyshev nodes, normal equations solved by Gaussian elimination with partial pivoting).
std::array<double, kFresnelDegree + 1> fresnel_polynomial(double eta) {
    constexpr int n = kFresnelDegree + 1;
    double a[n][n + 1] = {};
    constexpr int kNodes = 64;
    for (int s = 0; s < kNodes; ++s) {
        const double y = 0.5 - 0.5 * std::cos(kPi * (s + 0.5) / kNodes);
        const double f = fresnel_dielectric(y, eta);
        double powers[2 * n];
        powers[0] = 1.0;
        for (int k = 1; k < 2 * n; ++k) powers[k] = powers[k - 1] * y;
        for (int r = 0; r < n; ++r) {
            for (int c = 0; c < n; ++c) a[r][c] += powers[r + c];
            a[r][n] += powers[r] * f;
        }
    }
    for (int col = 0; col < n; ++col) {
        int pivot = col;
        for (int r = col + 1; r < n; ++r)
            if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
        for (int c = 0; c <= n; ++c) std::swap(a[col][c], a[pivot][c]);
        for (int r = col + 1; r < n; ++r) {
            const double factor = a[r][col] / a[col][col];
            for (int c = col; c <= n; ++c) a[r][c] -= factor * a[col][c];
        }
    }
    std::array<double, n> x{};
    for (int r = n - 1; r >= 0; --r) {
        double sum = a[r][n];
        for (int c = r + 1; c < n; ++c) sum -= a[r][c] * x[c];
        x[r] = sum / a[r][r];
    }
    return x;
}

double normal_cdf(double x, double mu, double variance) {
    return 0.5 * std::erfc(-(x - mu) / std::sqrt(2.0 * variance));
}

}  // namespace

double srbf(const glm::dvec3& w, const glm::dvec3& centre, double lambda) {
    return std::exp(2.0 * (glm::dot(glm::normalize(w), glm::normalize(centre)) - 1.0) / (lambda * lambda));
}

std::vector<double> linear_quadrature_nodes(double mu, double variance, int m) {
    if (m < 2) throw Error("linear quadrature needs m >= 2, got " + std::to_string(m));
    const double lambda = std::sqrt(2.0 * variance);
    std::vector<double> nodes{-0.5 * kPi, 0.5 * kPi};
    const double half = 0.5 * (m - 2) * lambda;
    for (int s = 0; s < m - 1; ++s) {
        const double x = m == 2 ? mu : mu - half + 2.0 * half * s / (m - 2);
        nodes.push_back(std::clamp(x, -0.5 * kPi, 0.5 * kPi));
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    return nodes;
}

glm::dvec3 linear_quadrature(std::span<const double> nodes, std::span<const glm::dvec3> values, double mu,
                             double variance) {
    // On [a, b]: integral of N (p x + q) = (p mu + q) (Phi(b) - Phi(a)) - p variance (N(b) - N(a)).
    glm::dvec3 sum(0.0);
    for (size_t s = 0; s + 1 < nodes.size(); ++s) {
        const double a = nodes[s], b = nodes[s + 1];
        const glm::dvec3 slope = (values[s + 1] - values[s]) / (b - a);
        const glm::dvec3 intercept = values[s] - slope * a;
        const double mass = normal_cdf(b, mu, variance) - normal_cdf(a, mu, variance);
        const double tail = gaussian(b - mu, variance) - gaussian(a - mu, variance);
        sum += (slope * mu + intercept) * mass - slope * (variance * tail);
    }
    return sum;
}

CircularGaussianMarschner::CircularGaussianMarschner(const MarschnerBcsdf& marschner,
                                                     std::shared_ptr<const CircularGaussianTables> tables, int m)
    : marschner_(marschner), tables_(std::move(tables)), m_(m), fresnel_fit_(fresnel_polynomial(marschner.params().eta)) {
    if (!tables_) throw Error("CircularGaussianMarschner needs the circular Gaussian tables");
    if (m_ < 2) throw Error("linear quadrature needs m >= 2, got " + std::to_string(m_));
}

std::array<double, 7> CircularGaussianMarschner::r_coefficients(double theta_d) const {
    // N_R = 1/4 |cos(phi/2)| F(cos(theta_d) |cos(phi/2)|) (Xu et al. 2011, Sec. 4.2.1 with h = -sin(phi/2)).
    std::array<double, 7> c{};
    const double cos_theta_d = std::cos(theta_d);
    double power = 1.0;
    for (int k = 0; k <= kFresnelDegree; ++k, power *= cos_theta_d) c[k + 1] = 0.25 * fresnel_fit_[k] * power;
    return c;
}

glm::dvec3 CircularGaussianMarschner::azimuthal(int p, double phi, double theta_d, double eta, double lambda_prime) const {
    if (p == 0) {
        const std::array<double, 7> c = r_coefficients(theta_d);
        double sum = 0.0;
        if (lambda_prime <= 0.0) {
            const double x = std::abs(std::cos(0.5 * phi));
            double power = 1.0;
            for (int k = 0; k < 7; ++k, power *= x) sum += c[k] * power;
        } else {
            // Xu 2011 Eq. 14 by table lookup; outside the table's lambda' range the nearest column is rescaled by
            // the lobe integral (exact in the narrow limit, where C_k -> integral |cos^k(phi/2)|).
            const Table2d& table = tables_->cosine;
            const double clamped = std::clamp(lambda_prime, table.begin0, table.end0);
            double cosine[7];
            table.lookup(clamped, std::abs(wrap_angle(phi)), cosine);
            const double scale = clamped == lambda_prime
                                     ? 1.0
                                     : circular_gaussian_integral(lambda_prime) / circular_gaussian_integral(clamped);
            for (int k = 0; k < 7; ++k) sum += c[k] * cosine[k] * scale;
        }
        return glm::dvec3(std::max(sum, 0.0));
    }
    const AzimuthalFit fit = p == 1 ? fit_tt(marschner_, *tables_, theta_d, eta) : fit_trt(marschner_, *tables_, theta_d, eta);
    return lambda_prime <= 0.0 ? fit.eval(phi) : fit.convolve(phi, lambda_prime);
}

LobeValues CircularGaussianMarschner::eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const HalfAngles angles = half_angles(di, dout);
    const double cos_theta_d = std::max(std::cos(angles.theta_d), kMinCos);
    const glm::dvec3 inv_cos2 = 1.0 / (cos_theta_d * cos_theta_d * glm::max(marschner_.energy(dout.theta), glm::dvec3(1.0)));
    const HairParams& params = marschner_.params();
    const std::array<double, 3> weight{params.weight_r, params.weight_tt, params.weight_trt};
    const auto lobes = marschner_.lobe_shapes();
    LobeValues out;
    out.count = 3;
    for (int p = 0; p < 3; ++p) {
        const double eta = p == 2 ? marschner_.eccentric_eta(angles.phi_h) : params.eta;
        const double m = gaussian_longitudinal(di.theta, dout.theta, lobes[p].shift, lobes[p].variance);
        out.value[p] = (weight[p] * m) * inv_cos2 * azimuthal(p, angles.phi, angles.theta_d, eta, 0.0);
    }
    return out;
}

glm::dvec3 CircularGaussianMarschner::single_scattering(const SrbfLight& light, const glm::dvec3& wo) const {
    if (!(light.lambda > 0.0 && std::isfinite(light.lambda)))
        throw Error("SRBF lambda must be finite and > 0, got " + std::to_string(light.lambda));
    const FiberDirection dout = fiber_direction(wo);
    const FiberDirection dj = fiber_direction(light.direction);
    const double lambda = light.lambda;
    const double lambda2 = lambda * lambda;
    const double delta_phi = wrap_angle(dout.phi - dj.phi);
    const HairParams& params = marschner_.params();
    const std::array<double, 3> weight{params.weight_r, params.weight_tt, params.weight_trt};
    // Xu 2011 Eq. 25-26 approximated: eta* at the light's centre, phi_h = (phi_o + phi_j) / 2.
    const double eta_trt = marschner_.eccentric_eta(0.5 * (dout.phi + dj.phi));
    const auto lobes = marschner_.lobe_shapes();
    glm::dvec3 sum(0.0);
    for (int p = 0; p < 3; ++p) {
        // exp(-(x - theta_j)^2 / lambda^2) N(x; c, v) = sqrt(pi) lambda N(theta_j; c, lambda^2/2 + v) N(x; mu*, v*).
        const double centre = 2.0 * lobes[p].shift - dout.theta;
        const double v = lobes[p].variance;
        const double v_star = 1.0 / (1.0 / v + 2.0 / lambda2);
        const double mu_star = v_star * (centre / v + 2.0 * dj.theta / lambda2);
        const double scale = std::sqrt(kPi) * lambda * gaussian(dj.theta - centre, 0.5 * lambda2 + v);
        if (!(scale > 0.0)) continue;
        const std::vector<double> nodes = linear_quadrature_nodes(mu_star, v_star, m_);
        std::vector<glm::dvec3> values(nodes.size());
        for (size_t s = 0; s < nodes.size(); ++s) {
            const double theta_i = nodes[s];
            const double theta_d = 0.5 * (dout.theta - theta_i);
            const double cos_i = std::cos(theta_i);
            const double cos_d = std::max(std::cos(theta_d), kMinCos);
            // Xu 2011 Eq. 11: the azimuthal SRBF bandwidth lambda' = lambda / sqrt(cos(theta_i) cos(theta_j)).
            const double lambda_prime = lambda / std::sqrt(std::max(cos_i * std::cos(dj.theta), 1e-12));
            values[s] = (cos_i * cos_i / (cos_d * cos_d)) *
                        azimuthal(p, delta_phi, theta_d, p == 2 ? eta_trt : params.eta, lambda_prime);
        }
        sum += (weight[p] * scale) * linear_quadrature(nodes, values, mu_star, v_star);
    }
    return light.coefficient * sum / glm::max(marschner_.energy(dout.theta), glm::dvec3(1.0));
}

std::vector<glm::dvec3> CircularGaussianMarschner::single_scattering(std::span<const SrbfLight> lights,
                                                                    std::span<const glm::dvec3> views) const {
    std::vector<glm::dvec3> radiance(views.size(), glm::dvec3(0.0));
    tbb::parallel_for(size_t(0), views.size(), [&](size_t k) {
        for (const SrbfLight& light : lights) radiance[k] += single_scattering(light, views[k]);
    });
    return radiance;
}

}  // namespace hairlod::bcsdf
