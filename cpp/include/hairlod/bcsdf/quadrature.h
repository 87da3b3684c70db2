#pragma once
// Numerical integration in double precision: fixed composite Gauss-Legendre for smooth integrands
// inside the models, and adaptive Gauss-Kronrod (G7/K15) as the brute-force ground truth of tests,
// benchmarks and tabulations. Integrands may return double or glm::dvec3 (error = largest channel).
#include <algorithm>
#include <array>
#include <cmath>

#include <glm/vec3.hpp>

namespace hairlod::bcsdf {

// 8-point Gauss-Legendre rule on [-1, 1] (nodes symmetric: +-x_k with weight w_k).
inline constexpr std::array<double, 4> kGaussLegendre8Nodes{0.1834346424956498, 0.5255324099163290,
                                                            0.7966664774136267, 0.9602898564975363};
inline constexpr std::array<double, 4> kGaussLegendre8Weights{0.3626837833783620, 0.3137066458778873,
                                                              0.2223810344533745, 0.1012285362903763};

// Composite 8-point Gauss-Legendre over [a, b] split into `panels` equal panels.
template <typename F>
auto integrate_gauss_legendre(F&& f, double a, double b, int panels) {
    using Value = decltype(f(a));
    Value sum{};
    const double width = (b - a) / panels;
    for (int panel = 0; panel < panels; ++panel) {
        const double centre = a + (panel + 0.5) * width;
        const double half = 0.5 * width;
        for (size_t k = 0; k < kGaussLegendre8Nodes.size(); ++k) {
            const double dx = half * kGaussLegendre8Nodes[k];
            sum += (half * kGaussLegendre8Weights[k]) * (f(centre - dx) + f(centre + dx));
        }
    }
    return sum;
}

struct QuadratureTolerance {
    double absolute = 1e-7;
    double relative = 1e-6;
    int max_depth = 30;  // bisections per branch
};

namespace detail {

inline double magnitude(double v) { return std::abs(v); }
inline double magnitude(const glm::dvec3& v) {
    return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

// Gauss-Kronrod 7/15 nodes and weights (Kronrod extension of the 7-point Gauss rule).
inline constexpr std::array<double, 8> kKronrodNodes{0.991455371120812639, 0.949107912342758525, 0.864864423359769073,
                                                     0.741531185599394440, 0.586087235467691130, 0.405845151377397167,
                                                     0.207784955007898468, 0.0};
inline constexpr std::array<double, 8> kKronrodWeights{0.022935322010529225, 0.063092092629978553,
                                                       0.104790010322250184, 0.140653259715525919,
                                                       0.169004726639267903, 0.190350578064785410,
                                                       0.204432940075298892, 0.209482141084727828};
// Gauss weights of the odd-indexed Kronrod nodes (1, 3, 5) and of the centre.
inline constexpr std::array<double, 4> kGaussWeights{0.129484966168869693, 0.279705391489276668,
                                                     0.381830050505118945, 0.417959183673469388};

template <typename F, typename Value>
Value gauss_kronrod(F& f, double a, double b, double& error) {
    const double centre = 0.5 * (a + b);
    const double half = 0.5 * (b - a);
    const Value f_centre = f(centre);
    Value kronrod = kKronrodWeights[7] * f_centre;
    Value gauss = kGaussWeights[3] * f_centre;
    for (int k = 0; k < 7; ++k) {
        const double dx = half * kKronrodNodes[k];
        const Value pair = f(centre - dx) + f(centre + dx);
        kronrod += kKronrodWeights[k] * pair;
        if (k % 2 == 1) gauss += kGaussWeights[k / 2] * pair;
    }
    error = magnitude(half * (kronrod - gauss));
    return half * kronrod;
}

template <typename F, typename Value>
Value adaptive(F& f, double a, double b, double absolute, const QuadratureTolerance& tolerance, int depth,
               const Value& estimate, double error) {
    if (error <= std::max(absolute, tolerance.relative * magnitude(estimate)) || depth >= tolerance.max_depth)
        return estimate;
    const double middle = 0.5 * (a + b);
    double error_left = 0.0, error_right = 0.0;
    const Value left = gauss_kronrod<F, Value>(f, a, middle, error_left);
    const Value right = gauss_kronrod<F, Value>(f, middle, b, error_right);
    return adaptive(f, a, middle, 0.5 * absolute, tolerance, depth + 1, left, error_left) +
           adaptive(f, middle, b, 0.5 * absolute, tolerance, depth + 1, right, error_right);
}

}  // namespace detail

// Adaptive Gauss-Kronrod: bisects until each piece's |K15 - G7| is below its share of the absolute
// tolerance or below the relative tolerance of its own estimate.
template <typename F>
auto integrate_adaptive(F&& f, double a, double b, const QuadratureTolerance& tolerance = {}) {
    using Value = decltype(f(a));
    double error = 0.0;
    const Value estimate = detail::gauss_kronrod<F, Value>(f, a, b, error);
    return detail::adaptive<F, Value>(f, a, b, tolerance.absolute, tolerance, 0, estimate, error);
}

// Adaptive integral over the rectangle [a0, b0] x [a1, b1], inner variable second: f(x0, x1).
template <typename F>
auto integrate_adaptive_2d(F&& f, double a0, double b0, double a1, double b1,
                           const QuadratureTolerance& tolerance = {}) {
    const double width0 = b0 - a0;
    QuadratureTolerance inner = tolerance;
    inner.absolute = tolerance.absolute / std::max(width0, 1e-300);
    return integrate_adaptive(
        [&](double x0) { return integrate_adaptive([&](double x1) { return f(x0, x1); }, a1, b1, inner); }, a0, b0,
        tolerance);
}

}  // namespace hairlod::bcsdf
