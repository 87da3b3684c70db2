#include "hairlod/bcsdf/microfacet.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kTableSize = 16;
// Roughness and cosine at the table's first nodes (0 would make the albedo's integrand singular).
constexpr double kMinTableAlpha = 1e-4;
constexpr double kMinTableCos = 0.02;
// The relative index at z = 1 is infinite (or 0); the last node is evaluated just inside.
constexpr double kMaxTableZ = 0.97;

// A frame whose z axis is the unit vector n.
struct Basis {
    glm::dvec3 s, t, n;
};

Basis basis_around(const glm::dvec3& n) {
    const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 s = glm::normalize(glm::cross(helper, n));
    return {s, glm::cross(n, s), n};
}

// The relative index of a table node: z = sqrt(|eta - 1| / (eta + 1)) inverted on either side of 1.
double eta_of_z(double z, bool inside) {
    const double z2 = std::min(z, kMaxTableZ) * std::min(z, kMaxTableZ);
    const double outside_eta = (1.0 + z2) / (1.0 - z2);
    return inside ? 1.0 / outside_eta : outside_eta;
}

struct EnergyTables {
    // [inside][alpha][cos][z] flattened; values 1 / E.
    std::array<std::vector<double>, 2> scale;

    EnergyTables() {
        for (int inside = 0; inside < 2; ++inside) {
            std::vector<double>& table = scale[inside];
            table.assign(kTableSize * kTableSize * kTableSize, 1.0);
            tbb::parallel_for(0, kTableSize * kTableSize * kTableSize, [&](int index) {
                const int ia = index / (kTableSize * kTableSize), ic = (index / kTableSize) % kTableSize,
                          iz = index % kTableSize;
                const double sqrt_alpha = double(ia) / (kTableSize - 1);
                const double alpha = std::max(sqrt_alpha * sqrt_alpha, kMinTableAlpha);
                const double cos_i = std::max(double(ic) / (kTableSize - 1), kMinTableCos);
                const double eta = eta_of_z(double(iz) / (kTableSize - 1), inside == 1);
                table[index] = 1.0 / std::max(ggx_dielectric_albedo(alpha, cos_i, eta, 32), 1e-6);
            });
        }
    }

    double lookup(double x, double y, double z, bool inside) const {
        const std::vector<double>& table = scale[inside ? 1 : 0];
        const auto split = [](double v, int& i0, double& f) {
            const double p = std::clamp(v, 0.0, 1.0) * (kTableSize - 1);
            i0 = std::min(static_cast<int>(p), kTableSize - 2);
            f = p - i0;
        };
        int ix, iy, iz;
        double fx, fy, fz;
        split(x, ix, fx);
        split(y, iy, fy);
        split(z, iz, fz);
        double value = 0.0;
        for (int dx = 0; dx < 2; ++dx)
            for (int dy = 0; dy < 2; ++dy)
                for (int dz = 0; dz < 2; ++dz) {
                    const double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy) * (dz ? fz : 1.0 - fz);
                    value += w * table[((ix + dx) * kTableSize + (iy + dy)) * kTableSize + (iz + dz)];
                }
        return value;
    }
};

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

double ggx_dielectric_energy_scale(double sqrt_alpha, double cos_i, double eta) {
    static const EnergyTables tables;
    const double z = std::sqrt(std::abs(eta - 1.0) / (eta + 1.0));
    return tables.lookup(sqrt_alpha, cos_i, z, eta < 1.0);
}

}  // namespace hairlod::bcsdf
