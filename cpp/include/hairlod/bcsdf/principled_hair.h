#pragma once
// Conversion from the inputs of Blender's Principled Hair BSDF node (Chiang model, Cycles 3.x and
// 4.x; Huang model, Cycles 4.0+) to HairParams, so that a scene's hair material drives evaluation,
// rendering and baking.
#include <glm/vec3.hpp>

#include "hairlod/bcsdf/hair_params.h"

namespace hairlod::bcsdf {

enum class PrincipledParametrization { AbsorptionCoefficient, MelaninConcentration, DirectColoring };
enum class PrincipledModel { Chiang, Huang };

// Socket values as Blender stores them; defaults are the node's defaults.
struct PrincipledHairInputs {
    PrincipledModel model = PrincipledModel::Chiang;
    PrincipledParametrization parametrization = PrincipledParametrization::DirectColoring;
    glm::dvec3 color{0.017513, 0.005763, 0.002059};           // Direct Coloring
    double melanin = 0.8;                                      // Melanin Concentration, in [0, 1]
    double melanin_redness = 1.0;                              // fraction of pheomelanin, in [0, 1]
    glm::dvec3 tint{1.0, 1.0, 1.0};                            // extra colour in melanin mode
    glm::dvec3 absorption_coefficient{0.245531, 0.52, 1.365};  // Absorption Coefficient
    double roughness = 0.3;                                    // -> beta_m
    double radial_roughness = 0.3;                             // -> beta_n
    double coat = 0.0;
    double ior = 1.55;
    double offset = 2.0 * 3.14159265358979323846 / 180.0;     // radians (an angle socket)
    double aspect_ratio = 0.85;                                // Huang: minor over major axis (> 1: swapped)
    double reflection = 1.0;                                   // Huang: R multiplier
    double transmission = 1.0;                                 // Huang: TT multiplier
    double secondary_reflection = 1.0;                         // Huang: TRT multiplier
};

// Melanin mode maps the [0, 1] slider to a concentration -log(max(1 - melanin, 1e-4)), splits it by
// redness into eumelanin and pheomelanin, and adds the absorption of `tint` (Chiang 2016 Eq. 9
// with radial roughness). Random Color and Random Roughness are per-strand noise and ignored.
// Roughnesses are clamped to [1e-3, 1] as Cycles does. Huang mode (Cycles 4.x): Roughness is the
// microfacet roughness and stands in for the radial roughness in the colour parametrizations, Radial
// Roughness and Coat are unused, an Aspect Ratio above 1 is read as its inverse (Cycles swaps the
// axes), Reflection / Transmission / Secondary Reflection weight R / TT / TRT; the colour becomes
// huang_sigma_a, and sigma_a, beta_m, beta_n the Chiang stand-in's (chiang_stand_in.h). The result is
// validated.
HairParams params_from_principled_hair(const PrincipledHairInputs& inputs);

}  // namespace hairlod::bcsdf
