#include "hairlod/bcsdf/dual_scattering.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/furnace.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;

// Attenuation-weighted mean of the lobes' shift and width (Xu et al. 2011, Sec. 4.3, after Eq. 33).
void lobe_averages(const LobeValues& energy, std::span<const LongitudinalLobe> shapes, glm::dvec3& alpha,
                   glm::dvec3& beta) {
    glm::dvec3 total(0.0), shift(0.0), variance(0.0);
    for (int p = 0; p < energy.count; ++p) {
        const double beta_p = 0.5 * std::sqrt(shapes[p].variance);
        total += energy.value[p];
        shift += shapes[p].shift * energy.value[p];
        variance += beta_p * beta_p * energy.value[p];
    }
    for (int c = 0; c < 3; ++c) {
        alpha[c] = total[c] > 0.0 ? shift[c] / total[c] : 0.0;
        beta[c] = total[c] > 0.0 ? std::sqrt(variance[c] / total[c]) : 0.0;
    }
}

}  // namespace

void backscattering_terms(DualScatteringSample& s, double d_b) {
    for (int c = 0; c < 3; ++c) {
        const double a_f = s.a_f[c];
        const double a_b = s.a_b[c];
        const double a_f2 = a_f * a_f;
        const double a_b2 = a_b * a_b;
        // a_f < 1 whenever any energy scatters backwards; keep the terms finite at the lossless limit.
        const double one_minus = std::max(1.0 - a_f2, 1e-12);
        s.A_1[c] = a_b * a_f2 / one_minus;
        s.A_3[c] = a_b * a_b2 * a_f2 / (one_minus * one_minus * one_minus);
        s.A_b[c] = s.A_1[c] + s.A_3[c];
        s.delta_b[c] = s.alpha_b[c] * (1.0 - 2.0 * a_b2 / (one_minus * one_minus)) +
                       s.alpha_f[c] * (2.0 * one_minus * one_minus + 4.0 * a_f2 * a_b2) /
                           (one_minus * one_minus * one_minus);
        const double beta_f = s.beta_f[c];
        const double beta_b = s.beta_b[c];
        const double single = std::sqrt(2.0 * beta_f * beta_f + beta_b * beta_b);
        const double triple = std::sqrt(2.0 * beta_f * beta_f + 3.0 * beta_b * beta_b);
        const double denominator = a_b + a_b * a_b2 * (2.0 * beta_f + 3.0 * beta_b);
        // As a_b -> 0 the ratio tends to the single-backscatter width.
        const double ratio = denominator > 0.0 ? (a_b * single + a_b * a_b2 * triple) / denominator : single;
        s.sigma_b[c] = (1.0 + d_b * a_f2) * ratio;
    }
}

DualScatteringSample dual_scattering(const FiberBcsdf& bcsdf, double theta_d, double d_b,
                                     const QuadratureTolerance& tolerance) {
    if (!(std::abs(theta_d) <= 0.5 * kPi)) throw Error("theta_d must be in [-pi/2, pi/2], got " + std::to_string(theta_d));
    if (!(d_b >= 0.0 && d_b <= 1.0)) throw Error("backscatter_density must be in [0, 1], got " + std::to_string(d_b));
    const glm::dvec3 wo = fiber_frame_direction(theta_d, 0.0);
    const auto lobes = [&](const glm::dvec3& wi) { return bcsdf.eval_lobes(wi, wo); };
    // Forward: the incident direction lies on the far side (|phi| > pi/2); backward: the near side.
    const LobeValues forward = integrate_directions(lobes, 0.5 * kPi, 1.5 * kPi, tolerance);
    const LobeValues backward = integrate_directions(lobes, -0.5 * kPi, 0.5 * kPi, tolerance);

    DualScatteringSample s;
    s.theta_d = theta_d;
    s.a_f = forward.sum();
    s.a_b = backward.sum();
    lobe_averages(forward, bcsdf.lobe_shapes(), s.alpha_f, s.beta_f);
    lobe_averages(backward, bcsdf.lobe_shapes(), s.alpha_b, s.beta_b);
    backscattering_terms(s, d_b);
    return s;
}

std::vector<DualScatteringSample> dual_scattering_table(const FiberBcsdf& bcsdf, std::span<const double> theta_d,
                                                        double d_b, const QuadratureTolerance& tolerance) {
    std::vector<DualScatteringSample> table(theta_d.size());
    tbb::parallel_for(size_t(0), theta_d.size(),
                      [&](size_t k) { table[k] = dual_scattering(bcsdf, theta_d[k], d_b, tolerance); });
    return table;
}

}  // namespace hairlod::bcsdf
