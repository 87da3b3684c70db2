#include "hairlod/bcsdf/hair_params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "hairlod/core/error.h"

namespace hairlod::bcsdf {
namespace {

// Expects validate() to throw an Error whose message names `name`.
void expect_rejected(const HairParams& params, const std::string& name) {
    try {
        params.validate();
        FAIL() << "accepted invalid " << name;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
}

TEST(HairParams, DefaultsAreValid) { EXPECT_NO_THROW(HairParams{}.validate()); }

TEST(HairParams, BadParametersNameTheParameter) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (double eta : {1.0, 0.5, nan}) {
        HairParams p;
        p.eta = eta;
        expect_rejected(p, "eta");
    }
    for (double sigma : {-0.1, nan, std::numeric_limits<double>::infinity()}) {
        HairParams p;
        p.sigma_a.y = sigma;
        expect_rejected(p, "sigma_a[1]");
    }
    for (double beta : {0.0, -0.2, 1.5, nan}) {
        HairParams p;
        p.beta_m = beta;
        expect_rejected(p, "beta_m");
        HairParams q;
        q.beta_n = beta;
        expect_rejected(q, "beta_n");
    }
    HairParams tilt;
    tilt.alpha = nan;
    expect_rejected(tilt, "alpha");
    HairParams coat;
    coat.coat = 1.5;
    expect_rejected(coat, "coat");
    for (double a : {0.7, 1.5, nan}) {
        HairParams p;
        p.eccentricity = a;
        expect_rejected(p, "eccentricity");
    }
    HairParams weight;
    weight.weight_tt = -1.0;
    expect_rejected(weight, "weight_tt");
}

TEST(HairParams, ChiangRoughnessMaps) {
    // Chiang et al. 2016, Eq. 7-8 at beta = 0.3 (by hand: (0.2178 + 0.07308)^2 = 0.084611, sqrt(pi/8) (0.0795 + 0.10746)).
    EXPECT_NEAR(longitudinal_variance(0.3), 0.084611, 1e-5);
    EXPECT_NEAR(logistic_scale(0.3), 0.117160, 1e-5);
    EXPECT_GT(longitudinal_variance(1.0), longitudinal_variance(0.9));
}

TEST(HairParams, LobeShapesFollowThePapers) {
    HairParams p;
    p.alpha = 0.05;
    p.coat = 0.5;
    const auto chiang = chiang_lobes(p);
    const double v = longitudinal_variance(p.beta_m);
    EXPECT_DOUBLE_EQ(chiang[0].shift, -0.05);
    EXPECT_DOUBLE_EQ(chiang[0].variance, longitudinal_variance(0.5 * p.beta_m));
    EXPECT_DOUBLE_EQ(chiang[1].variance, 0.25 * v);
    EXPECT_DOUBLE_EQ(chiang[2].shift, 0.1);
    EXPECT_DOUBLE_EQ(chiang[3].variance, 4.0 * v);
    const auto marschner = marschner_lobes(p);
    EXPECT_DOUBLE_EQ(marschner[1].shift, 0.025);
    EXPECT_DOUBLE_EQ(marschner[2].shift, 0.075);
    EXPECT_DOUBLE_EQ(marschner[2].variance, 4.0 * v);
}

TEST(HairParams, AbsorptionFromColourInvertsTheAlbedoFit) {
    // Chiang et al. 2016, Eq. 9 solved for the colour: c = exp(-sqrt(sigma_a) * polynomial(beta_n)).
    const glm::dvec3 color{0.6, 0.3, 0.1};
    for (double beta_n : {0.1, 0.5, 1.0}) {
        const glm::dvec3 sigma = sigma_a_from_color(color, beta_n);
        const double b = beta_n;
        const double poly = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * b * b * b + 5.574 * b * b * b * b +
                            0.245 * b * b * b * b * b;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(std::exp(-std::sqrt(sigma[c]) * poly), color[c], 1e-12);
    }
    EXPECT_EQ(sigma_a_from_color(glm::dvec3(1.0), 0.3), glm::dvec3(0.0));
    EXPECT_THROW(sigma_a_from_color(glm::dvec3(0.0, 0.5, 0.5), 0.3), Error);
}

TEST(HairParams, MelaninIsLinearInConcentration) {
    EXPECT_EQ(sigma_a_from_melanin(0.0, 0.0), glm::dvec3(0.0));
    const glm::dvec3 mix = sigma_a_from_melanin(1.3, 0.2);
    const glm::dvec3 sum = sigma_a_from_melanin(1.3, 0.0) + sigma_a_from_melanin(0.0, 0.2);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mix[c], sum[c], 1e-15);
    // Eumelanin absorbs blue most (brown-black hair).
    EXPECT_GT(mix.z, mix.y);
    EXPECT_GT(mix.y, mix.x);
    EXPECT_THROW(sigma_a_from_melanin(-1.0, 0.0), Error);
}

}  // namespace
}  // namespace hairlod::bcsdf
