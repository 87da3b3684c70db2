#include "hairlod/bcsdf/principled_hair.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hairlod/bcsdf/chiang_stand_in.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

namespace {

double unit_socket(const char* name, double value) {
    if (!(value >= 0.0 && value <= 1.0))
        throw Error(std::string("principled hair input ") + name + " = " + std::to_string(value) +
                    ": must be in [0, 1]");
    return value;
}

glm::dvec3 melanin_absorption(const PrincipledHairInputs& inputs, double beta_n) {
    const double melanin = unit_socket("melanin", inputs.melanin);
    const double redness = unit_socket("melanin_redness", inputs.melanin_redness);
    const double concentration = -std::log(std::max(1.0 - melanin, 1e-4));
    const glm::dvec3 pigment = sigma_a_from_melanin(concentration * (1.0 - redness), concentration * redness);
    return pigment + sigma_a_from_color(inputs.tint, beta_n);
}

}  // namespace

HairParams params_from_principled_hair(const PrincipledHairInputs& inputs) {
    HairParams params;
    const bool huang = inputs.model == PrincipledModel::Huang;
    params.eta = inputs.ior;
    params.beta_m = std::clamp(inputs.roughness, 1e-3, 1.0);
    params.beta_n = huang ? params.beta_m : std::clamp(inputs.radial_roughness, 1e-3, 1.0);
    params.coat = huang ? 0.0 : unit_socket("coat", inputs.coat);
    params.alpha = inputs.offset;
    switch (inputs.parametrization) {
        case PrincipledParametrization::AbsorptionCoefficient:
            params.sigma_a = inputs.absorption_coefficient;
            break;
        case PrincipledParametrization::MelaninConcentration:
            params.sigma_a = melanin_absorption(inputs, params.beta_n);
            break;
        case PrincipledParametrization::DirectColoring:
            params.sigma_a = sigma_a_from_color(inputs.color, params.beta_n);
            break;
    }
    if (!huang) {
        params.validate();
        return params;
    }
    params.fibre = FibreModel::Huang;
    params.microfacet_roughness = params.beta_m;
    if (!(inputs.aspect_ratio > 0.0))
        throw Error("principled hair input aspect_ratio = " + std::to_string(inputs.aspect_ratio) + ": must be > 0");
    params.aspect_ratio = inputs.aspect_ratio > 1.0 ? 1.0 / inputs.aspect_ratio : inputs.aspect_ratio;
    // Cycles clamps the lobe multipliers at 0.
    params.weight_r = std::max(inputs.reflection, 0.0);
    params.weight_tt = std::max(inputs.transmission, 0.0);
    params.weight_trt = std::max(inputs.secondary_reflection, 0.0);
    params.huang_sigma_a = params.sigma_a;
    params.validate();
    return chiang_stand_in(params).params;
}

}  // namespace hairlod::bcsdf
