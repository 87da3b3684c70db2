#include "hairlod/bcsdf/principled_hair.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hairlod/core/error.h"

namespace hairlod::bcsdf {
namespace {

TEST(PrincipledHair, AbsorptionCoefficientIsPassedThrough) {
    PrincipledHairInputs in;
    in.parametrization = PrincipledParametrization::AbsorptionCoefficient;
    in.absorption_coefficient = {0.1, 0.2, 0.3};
    in.roughness = 0.4;
    in.radial_roughness = 0.6;
    in.coat = 0.25;
    in.ior = 1.6;
    in.offset = 0.03;
    const HairParams p = params_from_principled_hair(in);
    EXPECT_EQ(p.sigma_a, glm::dvec3(0.1, 0.2, 0.3));
    EXPECT_DOUBLE_EQ(p.beta_m, 0.4);
    EXPECT_DOUBLE_EQ(p.beta_n, 0.6);
    EXPECT_DOUBLE_EQ(p.coat, 0.25);
    EXPECT_DOUBLE_EQ(p.eta, 1.6);
    EXPECT_DOUBLE_EQ(p.alpha, 0.03);
    EXPECT_DOUBLE_EQ(primary_roughness(p), 0.3);
}

TEST(PrincipledHair, MelaninConcentration) {
    PrincipledHairInputs in;
    in.parametrization = PrincipledParametrization::MelaninConcentration;
    in.melanin = 0.5;  // concentration -log(1 - 0.5) = log 2
    in.melanin_redness = 0.25;
    in.tint = {1.0, 1.0, 1.0};  // a white tint absorbs nothing
    const HairParams p = params_from_principled_hair(in);
    const glm::dvec3 expected = sigma_a_from_melanin(0.75 * std::log(2.0), 0.25 * std::log(2.0));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.sigma_a[c], expected[c], 1e-12);
    // A coloured tint adds its Chiang 2016 Eq. 9 absorption.
    in.tint = {1.0, 0.5, 0.5};
    const HairParams tinted = params_from_principled_hair(in);
    EXPECT_NEAR(tinted.sigma_a.x, expected.x, 1e-12);
    EXPECT_GT(tinted.sigma_a.y, expected.y);
    // Melanin 1 is clamped to a finite concentration -log(1e-4).
    in.melanin = 1.0;
    in.tint = {1.0, 1.0, 1.0};
    EXPECT_NEAR(params_from_principled_hair(in).sigma_a.x,
                sigma_a_from_melanin(0.75 * std::log(1e4), 0.25 * std::log(1e4)).x, 1e-9);
}

TEST(PrincipledHair, DirectColoringUsesRadialRoughness) {
    PrincipledHairInputs in;
    in.color = {0.5, 0.4, 0.3};
    in.radial_roughness = 0.7;
    const HairParams p = params_from_principled_hair(in);
    EXPECT_EQ(p.sigma_a, sigma_a_from_color(in.color, 0.7));
}

TEST(PrincipledHair, DefaultsAreBrownHairAndValid) {
    const HairParams p = params_from_principled_hair({});
    EXPECT_NEAR(p.alpha, 2.0 * 3.14159265358979 / 180.0, 1e-12);
    EXPECT_GT(p.sigma_a.z, p.sigma_a.x);
}

TEST(PrincipledHair, BadInputsNameTheSocketOrParameter) {
    PrincipledHairInputs in;
    in.coat = 2.0;
    try {
        params_from_principled_hair(in);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("coat"), std::string::npos);
    }
    in = {};
    in.ior = 0.9;
    try {
        params_from_principled_hair(in);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("eta"), std::string::npos);
    }
    in = {};
    in.parametrization = PrincipledParametrization::MelaninConcentration;
    in.melanin = -0.5;
    EXPECT_THROW(params_from_principled_hair(in), Error);
}

}  // namespace
}  // namespace hairlod::bcsdf

namespace hairlod::bcsdf {
namespace {

// Huang mode (Blender 4.x): the microfacet roughness is Roughness (also the colour's radial roughness),
// Radial Roughness and Coat are unused, an aspect ratio above 1 is its inverse, the lobe multipliers
// are clamped at 0, and sigma_a / beta_m / beta_n hold the Chiang stand-in.
TEST(PrincipledHair, HuangModeReadsItsOwnInputs) {
    PrincipledHairInputs in;
    in.model = PrincipledModel::Huang;
    in.parametrization = PrincipledParametrization::DirectColoring;
    in.color = {0.3, 0.2, 0.1};
    in.roughness = 0.4;
    in.radial_roughness = 0.9;
    in.coat = 0.7;
    in.aspect_ratio = 1.25;
    in.reflection = 0.5;
    in.transmission = -1.0;
    in.secondary_reflection = 2.0;
    const HairParams p = params_from_principled_hair(in);
    EXPECT_EQ(p.fibre, FibreModel::Huang);
    EXPECT_DOUBLE_EQ(p.microfacet_roughness, 0.4);
    EXPECT_DOUBLE_EQ(p.aspect_ratio, 0.8);
    EXPECT_DOUBLE_EQ(p.coat, 0.0);
    EXPECT_EQ(p.weight_r, 0.5);
    EXPECT_EQ(p.weight_tt, 0.0);
    EXPECT_EQ(p.weight_trt, 2.0);
    const glm::dvec3 sigma = sigma_a_from_color(in.color, 0.4);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(p.huang_sigma_a[c], sigma[c]);
    // The Chiang stand-in: the same roughness, its own absorption (the Huang fibre's albedo).
    EXPECT_DOUBLE_EQ(p.beta_m, 0.4);
    EXPECT_DOUBLE_EQ(p.beta_n, 0.4);
    EXPECT_NE(p.sigma_a, p.huang_sigma_a);
    in.aspect_ratio = 0.0;
    EXPECT_THROW(params_from_principled_hair(in), Error);
    // Chiang mode ignores the Huang inputs.
    in.model = PrincipledModel::Chiang;
    const HairParams chiang = params_from_principled_hair(in);
    EXPECT_EQ(chiang.fibre, FibreModel::Chiang);
    EXPECT_DOUBLE_EQ(chiang.beta_n, 0.9);
    EXPECT_DOUBLE_EQ(chiang.coat, 0.7);
}

}  // namespace
}  // namespace hairlod::bcsdf
