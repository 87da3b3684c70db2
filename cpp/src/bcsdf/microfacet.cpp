#include "hairlod/bcsdf/microfacet.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <mutex>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
// DielectricEnergyScale's table: nodes uniform in sqrt(cos_i) (1 / E is steepest at grazing light),
// each the albedo over this many visible normals squared; the cosine of its first node (at 0 the
// albedo's integrand is singular).
constexpr int kScaleNodes = 64;
constexpr int kScaleNormals = 192;
constexpr double kMinScaleCos = 1e-4;
// Tables kept for different (alpha, eta) before the oldest is dropped.
constexpr std::size_t kMaxCachedScales = 64;

// A frame whose z axis is the unit vector n.
struct Basis {
    glm::dvec3 s, t, n;
};

Basis basis_around(const glm::dvec3& n) {
    const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 s = glm::normalize(glm::cross(helper, n));
    return {s, glm::cross(n, s), n};
}

double scale_node_cos(int node) {
    const double x = double(node) / (kScaleNodes - 1);
    return std::max(x * x, kMinScaleCos);
}

std::shared_ptr<const std::vector<double>> make_scale_table(double alpha, double eta) {
    auto table = std::make_shared<std::vector<double>>(2 * kScaleNodes);
    tbb::parallel_for(0, 2 * kScaleNodes, [&](int index) {
        const bool inside = index >= kScaleNodes;
        const double albedo =
            ggx_dielectric_albedo(alpha, scale_node_cos(index % kScaleNodes), inside ? 1.0 / eta : eta, kScaleNormals);
        (*table)[index] = 1.0 / std::max(albedo, 1e-6);
    });
    return table;
}

// The tables made so far, by (alpha, eta): a renderer makes one fibre per material, tests and
// bindings make the same few again and again.
std::shared_ptr<const std::vector<double>> shared_scale_table(double alpha, double eta) {
    static std::mutex mutex;
    static std::vector<std::pair<std::pair<double, double>, std::shared_ptr<const std::vector<double>>>> cache;
    const std::pair<double, double> key(alpha, eta);
    {
        const std::lock_guard<std::mutex> lock(mutex);
        for (const auto& [k, table] : cache)
            if (k == key) return table;
    }
    auto table = make_scale_table(alpha, eta);
    const std::lock_guard<std::mutex> lock(mutex);
    if (cache.size() >= kMaxCachedScales) cache.erase(cache.begin());
    cache.emplace_back(key, table);
    return table;
}

}  // namespace

double ggx_distribution(double a2, double cos_mh) {
    if (!(cos_mh > 0.0)) return 0.0;
    const double c2 = cos_mh * cos_mh;
    const double denominator = (a2 - 1.0) * c2 + 1.0;
    return a2 / (kPi * denominator * denominator);
}

double ggx_lambda(double a2, double cos_m) {
    const double c2 = cos_m * cos_m;
    if (c2 < 1e-14) return 1e7;  // grazing: fully masked
    return 0.5 * (std::sqrt(1.0 + a2 * (1.0 - c2) / c2) - 1.0);
}

double ggx_shadowing(double a2, double cos_mi, double cos_mo) {
    return 1.0 / (1.0 + ggx_lambda(a2, cos_mi) + ggx_lambda(a2, cos_mo));
}

double ggx_shadowing_given_visible(double a2, double cos_mi, double cos_mo) {
    const double lambda_i = ggx_lambda(a2, cos_mi);
    return (1.0 + lambda_i) / (1.0 + lambda_i + ggx_lambda(a2, cos_mo));
}

glm::dvec3 sample_ggx_visible_normal(double alpha, const glm::dvec3& wi, const glm::dvec3& m, double u1, double u2) {
    const Basis b = basis_around(m);
    const glm::dvec3 local(glm::dot(wi, b.s), glm::dot(wi, b.t), glm::dot(wi, b.n));
    // Heitz 2018: stretch to the unit-roughness configuration, sample the projected hemisphere there.
    const glm::dvec3 v = glm::normalize(glm::dvec3(alpha * local.x, alpha * local.y, local.z));
    const double length2 = v.x * v.x + v.y * v.y;
    const glm::dvec3 t1 = length2 > 1e-14 ? glm::dvec3(-v.y, v.x, 0.0) / std::sqrt(length2) : glm::dvec3(1, 0, 0);
    const glm::dvec3 t2 = glm::cross(v, t1);
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    const double p1 = r * std::cos(phi);
    const double s = 0.5 * (1.0 + v.z);
    const double p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * r * std::sin(phi);
    const glm::dvec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * v;
    const glm::dvec3 h = glm::normalize(glm::dvec3(alpha * nh.x, alpha * nh.y, std::max(1e-12, nh.z)));
    return h.x * b.s + h.y * b.t + h.z * b.n;
}

double fresnel_dielectric_general(double cos_i, double eta, double& cos_t) {
    const double c = std::clamp(cos_i, 0.0, 1.0);
    const double sin2_t = (1.0 - c * c) / (eta * eta);
    if (sin2_t >= 1.0) {
        cos_t = 0.0;
        return 1.0;
    }
    cos_t = std::sqrt(1.0 - sin2_t);
    const double r_s = (c - eta * cos_t) / (c + eta * cos_t);
    const double r_p = (eta * c - cos_t) / (eta * c + cos_t);
    return 0.5 * (r_s * r_s + r_p * r_p);
}

glm::dvec3 refract_direction(const glm::dvec3& wi, const glm::dvec3& h, double cos_i, double cos_t, double eta) {
    const double inv_eta = 1.0 / eta;
    return (inv_eta * cos_i - cos_t) * h - inv_eta * wi;
}

double ggx_dielectric_albedo(double alpha, double cos_i, double eta, int samples) {
    const double a2 = alpha * alpha;
    const double c = std::clamp(cos_i, 1e-6, 1.0);
    const glm::dvec3 wi(std::sqrt(1.0 - c * c), 0.0, c), normal(0.0, 0.0, 1.0);
    double sum = 0.0;
    for (int i = 0; i < samples; ++i)
        for (int j = 0; j < samples; ++j) {
            const glm::dvec3 h = sample_ggx_visible_normal(alpha, wi, normal, (i + 0.5) / samples, (j + 0.5) / samples);
            const double cos_ih = glm::dot(wi, h);
            if (!(cos_ih > 0.0)) continue;
            double cos_t = 0.0;
            const double f = fresnel_dielectric_general(cos_ih, eta, cos_t);
            const glm::dvec3 reflected = 2.0 * cos_ih * h - wi;
            if (reflected.z > 0.0) sum += f * ggx_shadowing_given_visible(a2, c, reflected.z);
            if (cos_t > 0.0) {
                const glm::dvec3 transmitted = refract_direction(wi, h, cos_ih, cos_t, eta);
                if (transmitted.z < 0.0) sum += (1.0 - f) * ggx_shadowing_given_visible(a2, c, -transmitted.z);
            }
        }
    return sum / (samples * samples);
}

DielectricEnergyScale::DielectricEnergyScale(double alpha, double eta) : table_(shared_scale_table(alpha, eta)) {}

double DielectricEnergyScale::operator()(double cos_i, bool inside) const {
    const double p = std::sqrt(std::clamp(cos_i, 0.0, 1.0)) * (kScaleNodes - 1);
    const int i0 = std::min(static_cast<int>(p), kScaleNodes - 2);
    const double f = p - i0;
    const double* nodes = table_->data() + (inside ? kScaleNodes : 0);
    return (1.0 - f) * nodes[i0] + f * nodes[i0 + 1];
}

}  // namespace hairlod::bcsdf
