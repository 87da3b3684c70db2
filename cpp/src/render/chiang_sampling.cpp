#include "hairlod/render/chiang_sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/longitudinal.h"

namespace hairlod::render {

namespace {

using namespace hairlod::bcsdf;
constexpr double kPi = std::numbers::pi;

// The outgoing inclination rotated by -2 shift, as tilted_deon_longitudinal centres lobe p.
void tilted(double sin_o, double cos_o, double shift, double& sin_op, double& cos_op) {
    const double sin_2s = std::sin(2.0 * shift), cos_2s = std::cos(2.0 * shift);
    sin_op = sin_o * cos_2s - cos_o * sin_2s;
    cos_op = std::abs(cos_o * cos_2s + sin_o * sin_2s);
}

// d'Eon et al. 2011: the rough-cone lobe of variance v is the inclination of a direction drawn
// around the mirror cone direction with density proportional to exp(cos(gamma) / v); cos(gamma) by
// inverting its CDF, the cone azimuth uniform. Returns sin(theta_i).
double sample_longitudinal(double v, double sin_op, double cos_op, double u1, double u2) {
    u1 = std::max(u1, 1e-12);
    const double cos_gamma = std::clamp(1.0 + v * std::log(u1 + (1.0 - u1) * std::exp(-2.0 / v)), -1.0, 1.0);
    const double sin_gamma = std::sqrt(std::max(0.0, 1.0 - cos_gamma * cos_gamma));
    return std::clamp(-cos_gamma * sin_op + sin_gamma * std::cos(2.0 * kPi * u2) * cos_op, -1.0, 1.0);
}

// Chiang et al. 2016, Sec. 4.2: the logistic of scale s restricted to [-pi, pi], by inverting its CDF.
double sample_trimmed_logistic(double s, double u) {
    const double lo = 1.0 / (1.0 + std::exp(kPi / s)), hi = 1.0 / (1.0 + std::exp(-kPi / s));
    const double y = std::clamp(lo + u * (hi - lo), 1e-300, 1.0 - 1e-16);
    return std::clamp(-s * std::log(1.0 / y - 1.0), -kPi, kPi);
}

}  // namespace

std::array<double, 4> chiang_lobe_probabilities(const ChiangBcsdf& bcsdf, double sin_theta_o, double cos_theta_o,
                                                double h) {
    const HairParams& p = bcsdf.params();
    const FiberAttenuation att = fiber_attenuation(p.eta, p.sigma_a, sin_theta_o, cos_theta_o, h);
    const std::array<double, 4> weight{p.weight_r, p.weight_tt, p.weight_trt, p.weight_trt};
    std::array<double, 4> prob{};
    double sum = 0.0;
    for (int k = 0; k < 4; ++k) {
        prob[k] = weight[k] * (att.a[k].x + att.a[k].y + att.a[k].z) / 3.0;
        sum += prob[k];
    }
    if (!(sum > 0.0)) return {0.25, 0.25, 0.25, 0.25};
    for (double& q : prob) q /= sum;
    return prob;
}

BcsdfSample sample_chiang(const ChiangBcsdf& bcsdf, const glm::dvec3& wo, double h, const std::array<double, 4>& u) {
    const FiberDirection dout = fiber_direction(wo);
    const std::array<double, 4> prob = chiang_lobe_probabilities(bcsdf, dout.sin_theta, dout.cos_theta, h);
    // Choose the lobe with u[0].
    int lobe = 0;
    double cumulative = prob[0];
    while (lobe < 3 && u[0] >= cumulative) cumulative += prob[++lobe];
    const LongitudinalLobe shape = bcsdf.lobe_shapes()[lobe];

    double sin_op, cos_op;
    tilted(dout.sin_theta, dout.cos_theta, shape.shift, sin_op, cos_op);
    const double sin_i = sample_longitudinal(shape.variance, sin_op, cos_op, u[1], u[2]);
    const double cos_i = std::sqrt(std::max(0.0, 1.0 - sin_i * sin_i));

    double dphi;
    if (lobe < 3) {
        const HairParams& p = bcsdf.params();
        const FiberAttenuation att = fiber_attenuation(p.eta, p.sigma_a, dout.sin_theta, dout.cos_theta, h);
        dphi = ChiangBcsdf::deflection(lobe, att.gamma_o, att.gamma_t) + sample_trimmed_logistic(bcsdf.scale(), u[3]);
    } else {
        dphi = 2.0 * kPi * u[3];
    }
    // The evaluation reads phi = phi_i - phi_o.
    const double phi_i = dout.phi + dphi;
    BcsdfSample sample;
    sample.wi = glm::dvec3(sin_i, cos_i * std::cos(phi_i), cos_i * std::sin(phi_i));
    sample.pdf = chiang_pdf(bcsdf, sample.wi, wo, h);
    sample.value = bcsdf.eval_lobes(sample.wi, wo, h).sum() * std::max(cos_i, kMinCos);
    return sample;
}

double chiang_pdf(const ChiangBcsdf& bcsdf, const glm::dvec3& wi, const glm::dvec3& wo, double h) {
    const FiberDirection di = fiber_direction(wi);
    const FiberDirection dout = fiber_direction(wo);
    const HairParams& p = bcsdf.params();
    const FiberAttenuation att = fiber_attenuation(p.eta, p.sigma_a, dout.sin_theta, dout.cos_theta, h);
    const std::array<double, 4> prob = chiang_lobe_probabilities(bcsdf, dout.sin_theta, dout.cos_theta, h);
    const auto shapes = bcsdf.lobe_shapes();
    const double phi = di.phi - dout.phi;
    // M_p is normalised over cos(theta_i) d theta_i and N_p over phi, so M_p N_p is a density per
    // unit solid angle (d w = cos(theta) d theta d phi).
    double pdf = 0.0;
    for (int k = 0; k < 4; ++k) {
        if (prob[k] <= 0.0) continue;
        const double m = tilted_deon_longitudinal(di.sin_theta, di.cos_theta, dout.sin_theta, dout.cos_theta,
                                                  shapes[k].shift, shapes[k].variance);
        const double n = k < 3 ? bcsdf.azimuthal_lobe(phi - ChiangBcsdf::deflection(k, att.gamma_o, att.gamma_t))
                               : 1.0 / (2.0 * kPi);
        pdf += prob[k] * m * n;
    }
    return pdf;
}

namespace {

double far_field_offset(int k) { return -1.0 + (2.0 * k + 1.0) / kFarFieldOffsets; }

}  // namespace

BcsdfSample sample_chiang_far_field(const ChiangBcsdf& bcsdf, const glm::dvec3& wo, const std::array<double, 5>& u) {
    const int k = std::min(kFarFieldOffsets - 1, static_cast<int>(u[4] * kFarFieldOffsets));
    BcsdfSample sample = sample_chiang(bcsdf, wo, far_field_offset(k), {u[0], u[1], u[2], u[3]});
    sample.pdf = chiang_far_field_pdf(bcsdf, sample.wi, wo);
    return sample;
}

double chiang_far_field_pdf(const ChiangBcsdf& bcsdf, const glm::dvec3& wi, const glm::dvec3& wo) {
    double pdf = 0.0;
    for (int k = 0; k < kFarFieldOffsets; ++k) pdf += chiang_pdf(bcsdf, wi, wo, far_field_offset(k));
    return pdf / kFarFieldOffsets;
}

}  // namespace hairlod::render
