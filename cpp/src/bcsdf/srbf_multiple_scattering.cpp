#include "hairlod/bcsdf/srbf_multiple_scattering.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
// Periods summed when a wrapped normal is integrated (its standard deviation stays below 3.6).
constexpr int kWraps = 3;
constexpr int kLegendreNodes = 16;

double standard_normal_cdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n from the Chebyshev guesses).
struct GaussLegendre {
    std::array<double, kLegendreNodes> x{}, w{};
    GaussLegendre() {
        const int n = kLegendreNodes;
        for (int i = 0; i < n; ++i) {
            double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), derivative = 1.0;
            for (int iteration = 0; iteration < 100; ++iteration) {
                double p0 = 1.0, p1 = z;
                for (int k = 2; k <= n; ++k) {
                    const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                derivative = n * (z * p1 - p0) / (z * z - 1.0);
                const double step = p1 / derivative;
                z -= step;
                if (std::abs(step) < 1e-15) break;
            }
            x[i] = z;
            w[i] = 2.0 / ((1.0 - z * z) * derivative * derivative);
        }
    }
};

const GaussLegendre& gauss_legendre() {
    static const GaussLegendre rule;
    return rule;
}

// A circular Gaussian g^c(.; mu, lambda) read as its integral I(lambda) times a unit wrapped normal
// with the same peak: standard deviation I(lambda) / sqrt(2 pi) (lambda / sqrt(2) when narrow).
double wrapped_deviation(double lambda) { return circular_gaussian_integral(lambda) / std::sqrt(2.0 * kPi); }

// Mass of the unit wrapped normal (mean mu, deviation s) on the arc [a, b], b - a <= 2 pi.
double wrapped_arc_mass(double mu, double s, double a, double b) {
    double mass = 0.0;
    for (int k = -kWraps; k <= kWraps; ++k) {
        const double shift = 2.0 * kPi * k - mu;
        mass += standard_normal_cdf((b + shift) / s) - standard_normal_cdf((a + shift) / s);
    }
    return mass;
}

// The periodic triangle max(0, pi - |x|) (Xu 2011 Eq. 30's overlap of the two half-circle boxes) convolved
// with the unit wrapped normal of deviation s: each ramp max(0, y) becomes y Phi(y / s) + s phi(y / s).
double wrapped_triangle(double x, double s) {
    const auto ramp = [s](double y) {
        return y * standard_normal_cdf(y / s) + s * std::exp(-0.5 * y * y / (s * s)) / std::sqrt(2.0 * kPi);
    };
    double sum = 0.0;
    for (int k = -kWraps; k <= kWraps; ++k) {
        const double y = wrap_angle(x) + 2.0 * kPi * k;
        sum += ramp(y + kPi) - 2.0 * ramp(y) + ramp(y - kPi);
    }
    return sum;
}

// N(x; a, va) N(x; b, vb) = N(a; b, va + vb) N(x; mean, variance).
struct GaussianProduct {
    double scale, mean, variance;
};
GaussianProduct gaussian_product(double a, double va, double b, double vb) {
    const double sum = va + vb;
    return {gaussian(a - b, sum), (a * vb + b * va) / sum, va * vb / sum};
}

// Xu 2011 Eq. 11: the azimuthal SRBF bandwidth lambda' = lambda / sqrt(cos(theta_i) cos(theta_j)).
double azimuthal_bandwidth(double lambda, double cos_theta_i, double cos_theta_j) {
    return lambda / std::sqrt(std::max(cos_theta_i * cos_theta_j, 1e-12));
}

BackscatterTable::Terms lerp(const BackscatterTable::Terms& a, const BackscatterTable::Terms& b, double f) {
    return {a.A_b + f * (b.A_b - a.A_b), a.delta_b + f * (b.delta_b - a.delta_b), a.sigma_b + f * (b.sigma_b - a.sigma_b)};
}

void check_light(const SrbfLight& light) {
    if (!(light.lambda > 0.0 && std::isfinite(light.lambda)))
        throw Error("SRBF lambda must be finite and > 0, got " + std::to_string(light.lambda));
    if (!(glm::dot(light.direction, light.direction) > 0.0)) throw Error("SRBF direction must be non-zero");
}

void check_forward(const ForwardScattering& forward) {
    for (int c = 0; c < 3; ++c)
        if (!(forward.transmittance[c] >= 0.0 && forward.transmittance[c] <= 1.0))
            throw Error("forward_attenuation must be in [0, 1], got " + std::to_string(forward.transmittance[c]));
    if (!(forward.variance >= 0.0 && std::isfinite(forward.variance)))
        throw Error("forward_variance must be finite and >= 0, got " + std::to_string(forward.variance));
}

void check_density(double value, const char* name) {
    if (!(value >= 0.0 && value <= 1.0)) throw Error(std::string(name) + " must be in [0, 1], got " + std::to_string(value));
}

// Integral over theta_i of `product` (the spread light times a longitudinal lobe, one Gaussian) times
// cos^2(theta_i) / cos^2(theta_d) f(theta_d, cos_i), by the linear quadrature of Sec. 4.2.2 with m nodes.
template <typename F>
glm::dvec3 projected_quadrature(const GaussianProduct& product, double theta_o, int m, F&& f) {
    const std::vector<double> nodes = linear_quadrature_nodes(product.mean, product.variance, m);
    std::vector<glm::dvec3> values(nodes.size());
    for (size_t s = 0; s < nodes.size(); ++s) {
        const double theta_d = 0.5 * (theta_o - nodes[s]);
        const double cos_i = std::cos(nodes[s]);
        const double cos_d = std::max(std::cos(theta_d), kMinCos);
        values[s] = (cos_i * cos_i / (cos_d * cos_d)) * f(theta_d, cos_i);
    }
    return linear_quadrature(nodes, values, product.mean, product.variance);
}

}  // namespace

BackscatterTable::BackscatterTable(std::span<const DualScatteringSample> samples, double backscatter_density)
    : d_b_(backscatter_density) {
    check_density(backscatter_density, "backscatter_density");
    const size_t n = samples.size();
    if (n < 2) throw Error("the backscatter table needs at least 2 theta_d samples, got " + std::to_string(n));
    step_ = kPi / double(n - 1);
    for (size_t k = 0; k < n; ++k)
        if (std::abs(samples[k].theta_d - (-0.5 * kPi + step_ * double(k))) > 1e-9)
            throw Error("backscatter table samples must be uniform in theta_d over [-pi/2, pi/2]");
    nodes_.reserve(n);
    for (const DualScatteringSample& s : samples) nodes_.push_back({s.A_b, s.delta_b, s.sigma_b});
    running_.assign(n, Terms{});
    for (size_t k = 1; k < n; ++k) {
        const Terms& a = nodes_[k - 1];
        const Terms& b = nodes_[k];
        running_[k] = {running_[k - 1].A_b + 0.5 * step_ * (a.A_b + b.A_b),
                       running_[k - 1].delta_b + 0.5 * step_ * (a.delta_b + b.delta_b),
                       running_[k - 1].sigma_b + 0.5 * step_ * (a.sigma_b + b.sigma_b)};
    }
}

BackscatterTable::Terms BackscatterTable::at(double theta_d) const {
    const double t = std::clamp((theta_d + 0.5 * kPi) / step_, 0.0, double(nodes_.size() - 1));
    const size_t i = std::min(size_t(t), nodes_.size() - 2);
    return lerp(nodes_[i], nodes_[i + 1], t - double(i));
}

BackscatterTable::Terms BackscatterTable::cumulative(double theta_d) const {
    const double t = std::clamp((theta_d + 0.5 * kPi) / step_, 0.0, double(nodes_.size() - 1));
    const size_t i = std::min(size_t(t), nodes_.size() - 2);
    const double f = t - double(i);
    // The integral of the linear interpolant from node i to t.
    const Terms& a = nodes_[i];
    const Terms& b = nodes_[i + 1];
    const double w0 = step_ * f, w1 = 0.5 * step_ * f * f;
    return {running_[i].A_b + w0 * a.A_b + w1 * (b.A_b - a.A_b),
            running_[i].delta_b + w0 * a.delta_b + w1 * (b.delta_b - a.delta_b),
            running_[i].sigma_b + w0 * a.sigma_b + w1 * (b.sigma_b - a.sigma_b)};
}

BackscatterTable::Terms BackscatterTable::mean(double lo, double hi) const {
    lo = std::clamp(lo, -0.5 * kPi, 0.5 * kPi);
    hi = std::clamp(hi, -0.5 * kPi, 0.5 * kPi);
    if (hi - lo < 1e-9) {
        Terms terms = at(0.5 * (lo + hi));
        terms.A_b = glm::dvec3(0.0);
        return terms;
    }
    const Terms a = cumulative(lo), b = cumulative(hi);
    const double inv = 1.0 / (hi - lo);
    return {glm::dvec3(0.0), (b.delta_b - a.delta_b) * inv, (b.sigma_b - a.sigma_b) * inv};
}

BackscatterTable backscatter_table(const FiberBcsdf& bcsdf, int samples, double backscatter_density,
                                   const QuadratureTolerance& tolerance) {
    if (samples < 2) throw Error("backscatter table samples must be >= 2, got " + std::to_string(samples));
    std::vector<double> theta_d(static_cast<size_t>(samples));
    for (int k = 0; k < samples; ++k) theta_d[k] = -0.5 * kPi + kPi * k / (samples - 1);
    const std::vector<DualScatteringSample> table = dual_scattering_table(bcsdf, theta_d, backscatter_density, tolerance);
    return BackscatterTable(table, backscatter_density);
}

SrbfMultipleScattering::SrbfMultipleScattering(const CircularGaussianMarschner& fibre, BackscatterTable backscatter,
                                               double forward_density)
    : fibre_(fibre), backscatter_(std::move(backscatter)), d_f_(forward_density) {
    check_density(forward_density, "forward_density");
}

glm::dvec3 SrbfMultipleScattering::global_azimuthal(int p, double delta_phi, double theta_d, double eta,
                                                    double lambda_prime) const {
    if (p == 0) {
        // N_R is no circular Gaussian: Gauss-Legendre over the window of Xu 2011 Eq. 12's convolution (Eq. 14).
        const GaussLegendre& rule = gauss_legendre();
        glm::dvec3 sum(0.0);
        for (int g = 0; g < kLegendreNodes; ++g)
            sum += rule.w[g] * fibre_.azimuthal(0, delta_phi - 0.5 * kPi * rule.x[g], theta_d, eta, lambda_prime);
        return 0.5 * sum;  // (1/pi) (pi/2) sum of w_g f(u_g)
    }
    // Xu 2011 Eq. 16 / 20: lobes b g^c(phi; mu, lambda_t); their convolution with g^c(.; 0, lambda') has mass
    // b I(lambda_t) I(lambda') and, read as wrapped normals, the sum of the two variances; Xu 2011 Eq. 28 is its
    // mass on the half circle |phi - delta_phi| < pi/2, over pi.
    const MarschnerBcsdf& marschner = fibre_.marschner();
    const AzimuthalFit fit = p == 1 ? fit_tt(marschner, fibre_.tables(), theta_d, eta)
                                    : fit_trt(marschner, fibre_.tables(), theta_d, eta);
    const double light_mass = circular_gaussian_integral(lambda_prime);
    const double light_deviation = wrapped_deviation(lambda_prime);
    glm::dvec3 sum(0.0);
    for (int l = 0; l < fit.count; ++l) {
        const CircularGaussianLobe& lobe = fit.lobes[l];
        for (int c = 0; c < 3; ++c) {
            if (!(lobe.weight[c] > 0.0)) continue;
            const double deviation = wrapped_deviation(lobe.lambda[c]);
            const double s = std::sqrt(deviation * deviation + light_deviation * light_deviation);
            sum[c] += lobe.weight[c] * circular_gaussian_integral(lobe.lambda[c]) * light_mass *
                      wrapped_arc_mass(lobe.mu, s, delta_phi - 0.5 * kPi, delta_phi + 0.5 * kPi);
        }
    }
    return sum / kPi;
}

MultipleScatteringRadiance SrbfMultipleScattering::eval(const SrbfLight& light, const glm::dvec3& wo,
                                                        const ForwardScattering& forward) const {
    check_light(light);
    check_forward(forward);
    MultipleScatteringRadiance out;
    const glm::dvec3 weight_j = d_f_ * forward.transmittance * light.coefficient;  // Xu 2011 Eq. 3: d_f T_f L_j
    if (!(glm::dot(weight_j, weight_j) > 0.0)) return out;

    const FiberDirection dout = fiber_direction(wo);
    const FiberDirection dj = fiber_direction(light.direction);
    const double lambda = light.lambda;
    const double delta_phi = wrap_angle(dout.phi - dj.phi);
    const double cos_j = dj.cos_theta;
    // Xu 2011 Eq. 5 and 11: in theta the light is sqrt(pi) lambda N(theta; theta_j, lambda^2 / 2) (g^c ~ g, Sec. 4.2),
    // and the forward spread widens it to variance lambda^2 / 2 + sigma_f-bar^2.
    const double spread_scale = std::sqrt(kPi) * lambda;
    const double spread_variance = 0.5 * lambda * lambda + forward.variance;
    const int m = fibre_.quadrature_order();
    const HairParams& params = fibre_.marschner().params();
    const std::array<double, 3> lobe_weight{params.weight_r, params.weight_tt, params.weight_trt};
    // Xu 2011 Eq. 25-26 approximated as in single scattering: eta* at phi_h = (phi_o + phi_j) / 2.
    const double eta_trt = fibre_.marschner().eccentric_eta(0.5 * (dout.phi + dj.phi));
    const auto lobes = fibre_.marschner().lobe_shapes();

    // Sec. 4.3.1, Xu 2011 Eq. 27: the spread times M_t is one Gaussian in theta_i; the rest, cos^2(theta_i) /
    // cos^2(theta_d) N_t^G, by the linear quadrature of Sec. 4.2.2.
    glm::dvec3 global(0.0);
    for (int p = 0; p < 3; ++p) {
        const GaussianProduct product =
            gaussian_product(dj.theta, spread_variance, 2.0 * lobes[p].shift - dout.theta, lobes[p].variance);
        const double scale = spread_scale * product.scale;
        if (!(scale > 0.0)) continue;
        global += (lobe_weight[p] * scale) * projected_quadrature(product, dout.theta, m, [&](double theta_d, double cos_i) {
            return global_azimuthal(p, delta_phi, theta_d, p == 2 ? eta_trt : params.eta,
                                    azimuthal_bandwidth(lambda, cos_i, cos_j));
        });
    }
    out.global = weight_j * global / glm::max(fibre_.marschner().energy(dout.theta), glm::dvec3(1.0));

    // Sec. 4.3.2, Xu 2011 Eq. 29-31: Delta_b and sigma_b averaged over theta_i in theta_j -+ sigma_f (Eq. 31,
    // sigma_f the spread's bandwidth) so that the backscatter lobe is one Gaussian; A_b cos^2(theta_i) /
    // cos^2(theta_d) by linear quadrature; the azimuthal factor is Xu 2011 Eq. 30's triangle (pi - |phi_o - phi_j|)
    // / pi^2 convolved with the light's g^c(.; 0, lambda').
    const double sigma_f = std::sqrt(2.0 * spread_variance);
    const BackscatterTable::Terms averaged =
        backscatter_.mean(0.5 * (dout.theta - dj.theta - sigma_f), 0.5 * (dout.theta - dj.theta + sigma_f));
    const double d_b = backscatter_.backscatter_density();
    for (int c = 0; c < 3; ++c) {
        if (!(weight_j[c] > 0.0)) continue;
        const double sigma_b = std::max(averaged.sigma_b[c], 1e-6);
        const GaussianProduct product =
            gaussian_product(dj.theta, spread_variance, 2.0 * averaged.delta_b[c] - dout.theta, 4.0 * sigma_b * sigma_b);
        const double scale = spread_scale * product.scale;
        if (!(scale > 0.0)) continue;
        const glm::dvec3 integral = projected_quadrature(product, dout.theta, m, [&](double theta_d, double cos_i) {
            const double lambda_prime = azimuthal_bandwidth(lambda, cos_i, cos_j);
            const double azimuthal = circular_gaussian_integral(lambda_prime) *
                                     wrapped_triangle(delta_phi, wrapped_deviation(lambda_prime)) / (kPi * kPi);
            return glm::dvec3(backscatter_.at(theta_d).A_b[c] * azimuthal);
        });
        out.local[c] = weight_j[c] * d_b * scale * integral.x;
    }
    return out;
}

std::vector<MultipleScatteringRadiance> srbf_multiple_scattering_reference(
    const MarschnerBcsdf& fibre, const BackscatterTable& backscatter, std::span<const SrbfLight> lights,
    std::span<const ForwardScattering> forward, std::span<const glm::dvec3> wo, double forward_density,
    int theta_samples, int phi_samples) {
    if (forward.size() != lights.size()) throw Error("one forward-scattering state per light is needed");
    if (theta_samples < 8) throw Error("theta_samples must be >= 8, got " + std::to_string(theta_samples));
    if (phi_samples < 8 || phi_samples % 4 != 0)
        throw Error("phi_samples must be a multiple of 4 and >= 8, got " + std::to_string(phi_samples));
    check_density(forward_density, "forward_density");
    const int nt = theta_samples, np = phi_samples;
    const double h_theta = kPi / nt, h_phi = 2.0 * kPi / np;
    std::vector<double> theta(nt), phi(np);
    for (int k = 0; k < nt; ++k) theta[k] = -0.5 * kPi + (k + 0.5) * h_theta;
    for (int l = 0; l < np; ++l) phi[l] = -kPi + (l + 0.5) * h_phi;

    // The forward-scattered light field L_f (times d_f T_f L_j, summed over lights) on the grid.
    std::vector<glm::dvec3> field(size_t(nt) * np, glm::dvec3(0.0));
    std::vector<double> srbf_grid(size_t(nt) * np), window(size_t(nt) * np);
    for (size_t j = 0; j < lights.size(); ++j) {
        check_light(lights[j]);
        check_forward(forward[j]);
        const glm::dvec3 weight_j = forward_density * forward[j].transmittance * lights[j].coefficient;
        for (int k = 0; k < nt; ++k)
            for (int l = 0; l < np; ++l)
                srbf_grid[size_t(k) * np + l] = srbf(fiber_frame_direction(theta[k], phi[l]), lights[j].direction, lights[j].lambda);
        // Xu 2011 Eq. 5's s_f: the light arriving from phi_d lands on |phi_i - phi_d| <= pi/2 (ends count half).
        const int half = np / 4;
        for (int k = 0; k < nt; ++k)
            for (int l = 0; l < np; ++l) {
                double sum = 0.0;
                for (int o = -half; o <= half; ++o)
                    sum += (std::abs(o) == half ? 0.5 : 1.0) * srbf_grid[size_t(k) * np + (l + o + np) % np];
                window[size_t(k) * np + l] = sum * h_phi / kPi;
            }
        // The theta spread N(theta_i; theta_d, sigma_f-bar^2), integrated over each theta_d cell.
        const double deviation = std::sqrt(forward[j].variance);
        for (int i = 0; i < nt; ++i)
            for (int k = 0; k < nt; ++k) {
                double kernel = i == k ? 1.0 : 0.0;
                if (deviation > 0.0)
                    kernel = standard_normal_cdf((theta[k] + 0.5 * h_theta - theta[i]) / deviation) -
                             standard_normal_cdf((theta[k] - 0.5 * h_theta - theta[i]) / deviation);
                if (kernel < 1e-300) continue;
                for (int l = 0; l < np; ++l) field[size_t(i) * np + l] += (kernel * window[size_t(k) * np + l]) * weight_j;
            }
    }

    const double d_b = backscatter.backscatter_density();
    std::vector<MultipleScatteringRadiance> out(wo.size());
    tbb::parallel_for(size_t(0), wo.size(), [&](size_t v) {
        const FiberDirection dout = fiber_direction(wo[v]);
        MultipleScatteringRadiance sum;
        for (int i = 0; i < nt; ++i) {
            const double cos_i = std::cos(theta[i]);
            const double measure = cos_i * cos_i * h_theta * h_phi;  // cos(theta_i) dw_i
            const double theta_d = 0.5 * (dout.theta - theta[i]);
            const double cos_d = std::max(std::cos(theta_d), kMinCos);
            const BackscatterTable::Terms terms = backscatter.at(theta_d);
            glm::dvec3 back_longitudinal;
            for (int c = 0; c < 3; ++c) {
                const double sigma_b = std::max(terms.sigma_b[c], 1e-6);
                back_longitudinal[c] = terms.A_b[c] *
                                       gaussian(theta[i] - (2.0 * terms.delta_b[c] - dout.theta), 4.0 * sigma_b * sigma_b) /
                                       (kPi * cos_d * cos_d);
            }
            for (int l = 0; l < np; ++l) {
                const glm::dvec3& light = field[size_t(i) * np + l];
                if (light == glm::dvec3(0.0)) continue;
                const glm::dvec3 wi = fiber_frame_direction(theta[i], phi[l]);
                sum.global += light * fibre.eval(wi, wo[v]) * measure;
                if (std::abs(wrap_angle(dout.phi - phi[l])) < 0.5 * kPi)
                    sum.local += light * (d_b * back_longitudinal) * measure;
            }
        }
        out[v] = sum;
    });
    return out;
}

std::vector<MultipleScatteringRadiance> SrbfMultipleScattering::eval(std::span<const SrbfLight> lights,
                                                                     std::span<const ForwardScattering> forward,
                                                                     std::span<const glm::dvec3> views) const {
    if (forward.size() != lights.size()) throw Error("SRBF multiple scattering: one forward scattering per light");
    std::vector<MultipleScatteringRadiance> radiance(views.size());
    tbb::parallel_for(size_t(0), views.size(), [&](size_t k) {
        for (size_t j = 0; j < lights.size(); ++j) {
            const MultipleScatteringRadiance r = eval(lights[j], views[k], forward[j]);
            radiance[k].global += r.global;
            radiance[k].local += r.local;
        }
    });
    return radiance;
}

}  // namespace hairlod::bcsdf
