#pragma once
// The Chiang fibre that stands in for a Huang et al. 2022 microfacet fibre wherever a model is built on
// Chiang's lobes (dual scattering, the aggregated and real-time BCSDFs, the bake, the preview): the
// same index, tilt, lobe weights and roughness (beta_m = beta_n = the microfacet roughness), and the
// absorption that gives the light passing through its interior (TT, TRT and beyond) the energy it has
// in the Huang fibre, channel by channel, so that multiple scattering keeps the material's colour. The
// surface reflection R is each model's own: absorption cannot change it. Measured on the LoD test
// scenes against the Huang fibre path-traced (docs/lod-quality.md, "Blender 4.x hair").
#include <glm/vec3.hpp>

#include "hairlod/bcsdf/hair_params.h"

namespace hairlod::bcsdf {

// A fibre's albedo split into its surface reflection (R) and what leaves through the interior,
// averaged over the views on the sphere (8-point Gauss-Legendre in sin(theta_o) on each side).
struct FibreAlbedo {
    glm::dvec3 surface{0.0};
    glm::dvec3 interior{0.0};
    glm::dvec3 total() const { return surface + interior; }
};

struct ChiangStandIn {
    HairParams params;  // fibre Huang; sigma_a, beta_m, beta_n, coat those of the stand-in
    FibreAlbedo huang;
    // The stand-in's: its interior equals the Huang fibre's unless that lies outside what absorption
    // can give (above the lossless fibre's, or near 0: black hair, where the absorption stops at its bound).
    FibreAlbedo stand_in;
};

ChiangStandIn chiang_stand_in(const HairParams& huang);

// The Chiang fibre's albedo for `params` (its sigma_a, eta, weights): the h-averaged attenuations A_p
// (its lobes integrate to 1), R against the rest.
FibreAlbedo chiang_albedo(const HairParams& params);

// The Huang fibre's albedo for `params` (its huang_sigma_a, roughness, aspect ratio, weights): the mean
// throughput of its own samples (what path tracing carries; its evaluation double-counts totally
// internally reflected paths of a lossless fibre), split by the lobe each sample took, from a fixed seed.
FibreAlbedo huang_albedo(const HairParams& params);

}  // namespace hairlod::bcsdf
