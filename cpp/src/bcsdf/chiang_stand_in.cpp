#include "hairlod/bcsdf/chiang_stand_in.h"

#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "hairlod/bcsdf/attenuation.h"
#include "hairlod/bcsdf/huang.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {

namespace {

constexpr int kSamplesPerView = 4096;
constexpr int kBisections = 48;
constexpr double kMaxAbsorption = 1000.0;
constexpr uint64_t kSeed = 0x68616972;

// Views at the 8-point Gauss-Legendre nodes of sin(theta_o) in [0, 1] (the fibres are symmetric in
// theta_o up to their tilt, which the other half would mirror), weights summing to 1.
template <typename F>
FibreAlbedo average_over_views(F&& albedo_at) {
    FibreAlbedo sum;
    for (size_t k = 0; k < kGaussLegendre8Nodes.size(); ++k)
        for (double sign : {-1.0, 1.0}) {
            const double sin_theta = 0.5 * (1.0 + sign * kGaussLegendre8Nodes[k]);
            const FibreAlbedo at = albedo_at(sin_theta, std::sqrt(1.0 - sin_theta * sin_theta));
            const double weight = 0.5 * kGaussLegendre8Weights[k];
            sum.surface += weight * at.surface;
            sum.interior += weight * at.interior;
        }
    return sum;
}

}  // namespace

FibreAlbedo chiang_albedo(const HairParams& params) {
    return average_over_views([&](double sin_theta, double cos_theta) {
        const std::array<glm::dvec3, 4> a = mean_fiber_attenuation(params.eta, params.sigma_a, sin_theta, cos_theta);
        return FibreAlbedo{params.weight_r * a[0], params.weight_tt * a[1] + params.weight_trt * (a[2] + a[3])};
    });
}

FibreAlbedo huang_albedo(const HairParams& params) {
    const HuangBcsdf model(params);
    // A fixed seed: the same parameters give the same albedo (and stand-in) every time.
    std::mt19937_64 engine(kSeed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    return average_over_views([&](double sin_theta, double cos_theta) {
        FibreAlbedo sum;
        for (int k = 0; k < kSamplesPerView; ++k) {
            std::array<double, 11> u;
            for (double& d : u) d = uniform(engine);
            // The view's azimuth turns with the sample: it matters for an elliptical fibre only.
            const double phi = 2.0 * std::numbers::pi * uniform(engine);
            const glm::dvec3 wo(sin_theta, cos_theta * std::cos(phi), cos_theta * std::sin(phi));
            const FibreSample s = model.sample(wo, u);
            (s.lobe == 0 ? sum.surface : sum.interior) += s.weight / double(kSamplesPerView);
        }
        return sum;
    });
}

ChiangStandIn chiang_stand_in(const HairParams& huang) {
    huang.validate();
    ChiangStandIn result;
    result.params = huang;
    result.params.beta_m = result.params.beta_n = huang.microfacet_roughness;
    result.params.coat = 0.0;
    result.huang = huang_albedo(huang);
    // The interior's energy falls as the absorption grows: bisection per channel, all three at once.
    glm::dvec3 lo(0.0), hi(kMaxAbsorption);
    for (int step = 0; step < kBisections; ++step) {
        result.params.sigma_a = 0.5 * (lo + hi);
        const glm::dvec3 interior = chiang_albedo(result.params).interior;
        for (int c = 0; c < 3; ++c) (interior[c] > result.huang.interior[c] ? lo[c] : hi[c]) = result.params.sigma_a[c];
    }
    result.params.sigma_a = 0.5 * (lo + hi);
    result.stand_in = chiang_albedo(result.params);
    return result;
}

}  // namespace hairlod::bcsdf
