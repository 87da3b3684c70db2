#include "hairlod/bcsdf/hair_params.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

std::string number(double value) {
    return std::isnan(value) ? std::string("NaN") : std::to_string(value);
}

void require(bool ok, const char* name, double value, const char* expectation) {
    if (!ok) throw Error(std::string("hair parameter ") + name + " = " + number(value) + ": " + expectation);
}

void require_unit_roughness(const char* name, double beta) {
    require(beta > 0.0 && beta <= 1.0, name, beta, "must be in (0, 1]");
}

}  // namespace

void HairParams::validate() const {
    require(std::isfinite(eta) && eta > 1.0, "eta", eta, "must be finite and > 1");
    const char* sigma_names[3] = {"sigma_a[0]", "sigma_a[1]", "sigma_a[2]"};
    for (int c = 0; c < 3; ++c)
        require(std::isfinite(sigma_a[c]) && sigma_a[c] >= 0.0, sigma_names[c], sigma_a[c],
                "absorption must be finite and >= 0");
    require_unit_roughness("beta_m", beta_m);
    require_unit_roughness("beta_n", beta_n);
    require(std::isfinite(alpha) && std::abs(alpha) < std::numbers::pi / 8.0, "alpha", alpha,
            "cuticle tilt must be finite and below pi/8 in magnitude");
    require(coat >= 0.0 && coat <= 1.0, "coat", coat, "must be in [0, 1]");
    // Xu et al. 2011, Eq. 24: eta*_1,2 = 2 (eta - 1) a^(+-2) - eta + 2 stays > 1 iff a^2 and 1/a^2 exceed 1/2.
    require(eccentricity > std::numbers::sqrt2 / 2.0 && eccentricity < std::numbers::sqrt2, "eccentricity",
            eccentricity, "must be in (1/sqrt(2), sqrt(2)) so that eta* of Eq. 24 stays > 1");  // Xu 2011 Eq. 24
    require(std::isfinite(weight_r) && weight_r >= 0.0, "weight_r", weight_r, "must be finite and >= 0");
    require(std::isfinite(weight_tt) && weight_tt >= 0.0, "weight_tt", weight_tt, "must be finite and >= 0");
    require(std::isfinite(weight_trt) && weight_trt >= 0.0, "weight_trt", weight_trt, "must be finite and >= 0");
    require(std::isfinite(microfacet_roughness) && microfacet_roughness >= 1e-3 && microfacet_roughness <= 1.0,
            "microfacet_roughness", microfacet_roughness, "must be in [0.001, 1]");
    const char* huang_names[3] = {"huang_sigma_a[0]", "huang_sigma_a[1]", "huang_sigma_a[2]"};
    for (int c = 0; c < 3; ++c)
        require(std::isfinite(huang_sigma_a[c]) && huang_sigma_a[c] >= 0.0, huang_names[c], huang_sigma_a[c],
                "absorption must be finite and >= 0");
    require(std::isfinite(aspect_ratio) && aspect_ratio >= 0.1 && aspect_ratio <= 1.0, "aspect_ratio", aspect_ratio,
            "must be in [0.1, 1] (minor over major axis)");
}

double primary_roughness(const HairParams& params) {
    return std::clamp((1.0 - params.coat) * params.beta_m, 1e-3, 1.0);
}

double longitudinal_variance(double beta_m) {
    const double b = beta_m;
    const double root = 0.726 * b + 0.812 * b * b + 3.7 * std::pow(b, 20);
    return root * root;
}

double logistic_scale(double beta_n) {
    const double b = beta_n;
    return std::sqrt(std::numbers::pi / 8.0) * (0.265 * b + 1.194 * b * b + 5.372 * std::pow(b, 22));
}

std::array<LongitudinalLobe, 4> chiang_lobes(const HairParams& params) {
    const double v = longitudinal_variance(params.beta_m);
    const double a = params.alpha;
    return {{{-a, longitudinal_variance(primary_roughness(params))},
             {0.5 * a, 0.25 * v},
             {2.0 * a, 4.0 * v},
             {0.0, 4.0 * v}}};
}

std::array<LongitudinalLobe, 3> marschner_lobes(const HairParams& params) {
    const double v = longitudinal_variance(params.beta_m);
    const double a = params.alpha;
    return {{{-a, longitudinal_variance(primary_roughness(params))}, {0.5 * a, 0.25 * v}, {1.5 * a, 4.0 * v}}};
}

glm::dvec3 sigma_a_from_color(const glm::dvec3& color, double beta_n) {
    require_unit_roughness("beta_n", beta_n);
    const char* names[3] = {"color[0]", "color[1]", "color[2]"};
    for (int c = 0; c < 3; ++c)
        require(color[c] > 0.0 && color[c] <= 1.0, names[c], color[c], "must be in (0, 1]");
    const double b = beta_n;
    const double denominator =
        5.969 - 0.215 * b + 2.532 * b * b - 10.73 * std::pow(b, 3) + 5.574 * std::pow(b, 4) + 0.245 * std::pow(b, 5);
    glm::dvec3 sigma;
    for (int c = 0; c < 3; ++c) {
        const double root = std::log(color[c]) / denominator;
        sigma[c] = root * root;
    }
    return sigma;
}

glm::dvec3 sigma_a_from_melanin(double eumelanin, double pheomelanin) {
    require(std::isfinite(eumelanin) && eumelanin >= 0.0, "eumelanin", eumelanin, "must be finite and >= 0");
    require(std::isfinite(pheomelanin) && pheomelanin >= 0.0, "pheomelanin", pheomelanin, "must be finite and >= 0");
    // Cycles' principled hair absorption per unit concentration, linear sRGB.
    const glm::dvec3 eumelanin_sigma_a{0.506, 0.841, 1.653};
    const glm::dvec3 pheomelanin_sigma_a{0.343, 0.733, 1.924};
    return eumelanin * eumelanin_sigma_a + pheomelanin * pheomelanin_sigma_a;
}

}  // namespace hairlod::bcsdf
