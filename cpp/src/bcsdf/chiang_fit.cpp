#include "hairlod/bcsdf/chiang_fit.h"

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/huang.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kThetaNodes = 12, kPhiNodes = 16;
constexpr double kViewThetasDegrees[] = {-50.0, -20.0, 10.0, 40.0};
constexpr double kViewPhis[] = {0.0, 0.5 * kPi};  // along the major and the minor axis
constexpr int kViews = 8;
constexpr double kMinBeta = 0.02, kMaxBeta = 1.0;
constexpr int kGoldenIterations = 12;

struct Grid {
    std::vector<glm::dvec3> wi, wo;  // kViews x kThetaNodes x kPhiNodes pairs
};

Grid fit_grid() {
    Grid g;
    for (double theta_o_deg : kViewThetasDegrees)
        for (double phi_o : kViewPhis) {
            const double to = theta_o_deg * kPi / 180.0;
            const glm::dvec3 wo(std::sin(to), std::cos(to) * std::cos(phi_o), std::cos(to) * std::sin(phi_o));
            for (int t = 0; t < kThetaNodes; ++t) {
                const double ti = -0.5 * kPi + (t + 0.5) * kPi / kThetaNodes;
                for (int p = 0; p < kPhiNodes; ++p) {
                    const double pi_angle = phi_o - kPi + (p + 0.5) * 2.0 * kPi / kPhiNodes;
                    g.wi.push_back({std::sin(ti), std::cos(ti) * std::cos(pi_angle), std::cos(ti) * std::sin(pi_angle)});
                    g.wo.push_back(wo);
                }
            }
        }
    return g;
}

// Luminance of S cos(theta_i) at every grid pair.
std::vector<double> luminance(const FiberBcsdf& model, const Grid& g) {
    std::vector<double> out(g.wi.size());
    tbb::parallel_for(size_t(0), g.wi.size(), [&](size_t k) {
        const glm::dvec3 v = model.eval(g.wi[k], g.wo[k]);
        const double cos_i = std::sqrt(std::max(0.0, 1.0 - g.wi[k].x * g.wi[k].x));
        out[k] = (0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z) * cos_i;
    });
    return out;
}

// Profiles over theta_i (summed over phi) or over phi (summed over theta_i), per view.
std::vector<double> profile(const std::vector<double>& values, bool longitudinal) {
    std::vector<double> out(kViews * (longitudinal ? kThetaNodes : kPhiNodes), 0.0);
    for (int v = 0; v < kViews; ++v)
        for (int t = 0; t < kThetaNodes; ++t)
            for (int p = 0; p < kPhiNodes; ++p) {
                const double value = values[(v * kThetaNodes + t) * kPhiNodes + p];
                out[v * (longitudinal ? kThetaNodes : kPhiNodes) + (longitudinal ? t : p)] += value;
            }
    return out;
}

double squared_distance(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0.0;
    for (size_t k = 0; k < a.size(); ++k) sum += (a[k] - b[k]) * (a[k] - b[k]);
    return sum;
}

double golden_section(const std::function<double(double)>& cost) {
    const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
    double lo = std::log(kMinBeta), hi = std::log(kMaxBeta);
    double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo);
    double f1 = cost(std::exp(x1)), f2 = cost(std::exp(x2));
    for (int k = 0; k < kGoldenIterations; ++k) {
        if (f1 < f2) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - ratio * (hi - lo);
            f1 = cost(std::exp(x1));
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + ratio * (hi - lo);
            f2 = cost(std::exp(x2));
        }
    }
    return std::exp(0.5 * (lo + hi));
}

HairParams with_betas(HairParams p, double beta_m, double beta_n) {
    p.beta_m = beta_m;
    p.beta_n = beta_n;
    p.coat = 0.0;
    return p;
}

}  // namespace

ChiangFit fit_chiang_to_huang(const HairParams& huang) {
    huang.validate();
    const Grid grid = fit_grid();
    const std::vector<double> target = luminance(HuangBcsdf(huang), grid);
    const std::vector<double> target_m = profile(target, true), target_n = profile(target, false);
    const double norm2 = squared_distance(target, std::vector<double>(target.size(), 0.0));
    const auto chiang = [&](double beta_m, double beta_n) {
        return luminance(ChiangBcsdf(with_betas(huang, beta_m, beta_n)), grid);
    };
    const double start = huang.microfacet_roughness;
    const double beta_m = golden_section([&](double b) { return squared_distance(profile(chiang(b, start), true), target_m); });
    const double beta_n = golden_section([&](double b) { return squared_distance(profile(chiang(beta_m, b), false), target_n); });
    ChiangFit fit;
    fit.params = with_betas(huang, beta_m, beta_n);
    const double scale = norm2 > 0.0 ? 1.0 / std::sqrt(norm2) : 0.0;
    fit.relative_error = std::sqrt(squared_distance(chiang(beta_m, beta_n), target)) * scale;
    fit.start_error = std::sqrt(squared_distance(chiang(start, start), target)) * scale;
    return fit;
}

}  // namespace hairlod::bcsdf
