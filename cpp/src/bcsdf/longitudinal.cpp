#include "hairlod/bcsdf/longitudinal.h"

#include <cmath>
#include <numbers>

namespace hairlod::bcsdf {

double log_scaled_bessel_i0(double x) {
    x = std::abs(x);
    if (x < 50.0) {
        // I_0(x) = sum_k (x^2 / 4)^k / (k!)^2; all terms are positive, so stop when they stop counting.
        const double q = 0.25 * x * x;
        double term = 1.0;
        double sum = 1.0;
        for (int k = 1; k < 500 && term > 1e-17 * sum; ++k) {
            term *= q / (double(k) * double(k));
            sum += term;
        }
        return std::log(sum) - x;
    }
    double term = 1.0;
    double sum = 1.0;
    for (int k = 1; k < 30 && term > 1e-17; ++k) {
        const double odd = 2.0 * k - 1.0;
        term *= odd * odd / (8.0 * k * x);
        sum += term;
    }
    return std::log(sum) - 0.5 * std::log(2.0 * std::numbers::pi * x);
}

double log_bessel_i0(double x) { return std::abs(x) + log_scaled_bessel_i0(x); }

double deon_longitudinal(double sin_theta_i, double cos_theta_i, double sin_theta_o, double cos_theta_o, double v) {
    const double a = sin_theta_i * sin_theta_o / v;
    const double b = cos_theta_i * cos_theta_o / v;
    // log(2 v sinh(1/v)) = log v + 1/v + log(1 - e^(-2/v)), safe for small v.
    const double log_normalisation = std::log(v) + 1.0 / v + std::log1p(-std::exp(-2.0 / v));
    return std::exp(log_bessel_i0(b) - a - log_normalisation);
}

double tilted_deon_longitudinal(double sin_theta_i, double cos_theta_i, double sin_theta_o, double cos_theta_o,
                                double shift, double v) {
    // theta_o' = theta_o - 2 shift; |cos| reflects a rotation past the pole back into [-pi/2, pi/2],
    // which leaves M unchanged because M depends on theta_o only through sin and cos.
    const double sin_2s = std::sin(2.0 * shift);
    const double cos_2s = std::cos(2.0 * shift);
    const double sin_theta_op = sin_theta_o * cos_2s - cos_theta_o * sin_2s;
    const double cos_theta_op = std::abs(cos_theta_o * cos_2s + sin_theta_o * sin_2s);
    return deon_longitudinal(sin_theta_i, cos_theta_i, sin_theta_op, cos_theta_op, v);
}

double gaussian(double x, double variance) {
    return std::exp(-0.5 * x * x / variance) / std::sqrt(2.0 * std::numbers::pi * variance);
}

double wrapped_gaussian(double x, double variance) {
    constexpr double kTwoPi = 2.0 * std::numbers::pi;
    x = std::remainder(x, kTwoPi);
    if (variance <= 4.0) {
        // Standard deviation <= 2: the periods beyond x -+ 6 pi lie more than 5.5 deviations out (< 1e-13).
        double sum = 0.0;
        for (int k = -3; k <= 3; ++k) sum += gaussian(x + kTwoPi * k, variance);
        return sum;
    }
    // Wide lobes: the Fourier series of the wrapped normal, (1 + 2 sum_k e^(-k^2 v / 2) cos(k x)) / (2 pi),
    // whose terms fall below 1e-17 by k = 7 when v > 4.
    double sum = 1.0;
    for (int k = 1; k <= 7; ++k) sum += 2.0 * std::exp(-0.5 * k * k * variance) * std::cos(k * x);
    return sum / kTwoPi;
}

double gaussian_longitudinal(double theta_i, double theta_o, double shift, double variance) {
    return gaussian(theta_i + theta_o - 2.0 * shift, variance);
}

}  // namespace hairlod::bcsdf
