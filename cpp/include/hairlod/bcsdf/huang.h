#pragma once
// The microfacet hair fibre of Huang, Hullin and Hanika 2022 ("A Microfacet-based Hair Scattering
// Model"), the default of Blender 4.x's Principled Hair BSDF, written to behave as Cycles' does:
// an elliptical fibre (major axis 1 along the frame's +y, minor axis aspect_ratio along +z, tangent
// +x) whose cuticle is a rough GGX dielectric tilted by alpha. R is integrated over the fibre's visible
// width; TT and TRT follow microfacet-refracted paths through the interior (absorption along the
// elliptical chords), each interface scaled by the inverse directional albedo of a rough dielectric
// (microfacet.h); TRRT+ is the geometric series of the last interactions with Chiang et al. 2016's
// longitudinal lobe (variance 4 x roughness) and a uniform azimuth. Far field: the whole width a
// pixel sees, which is what a renderer sees of a fibre thinner than a pixel. Its absorption is
// HairParams::huang_sigma_a (sigma_a is the Chiang stand-in's, chiang_stand_in.h).
#include <array>
#include <span>

#include <glm/vec4.hpp>

#include "hairlod/bcsdf/bcsdf.h"
#include "hairlod/bcsdf/microfacet.h"

namespace hairlod::bcsdf {

// A direction drawn for the light from wo, with the throughput S cos(theta_i) / pdf. As Cycles
// does, the sample carries its weight and no usable density (the model has no closed-form pdf).
struct FibreSample {
    glm::dvec3 wi{0.0};
    glm::dvec3 weight{0.0};
    int lobe = -1;  // 0 R, 1 TT, 2 TRT, 3 TRRT+; -1 when no path leaves
    // The throughput the model's visibility rules drop on this path (Cycles' rules): light arriving
    // where the tilted cuticle faces away from wo, and paths that a cuticle sends into the fibre's
    // own surface. Absorption and masking are not counted. For a lossless fibre weight + discarded
    // averages to 1: the model's energy is 1 minus the mean of discarded.
    glm::dvec3 discarded{0.0};
};

class HuangBcsdf final : public FiberBcsdf {
public:
    // residual_samples: visible-normal samples per width node for the TT / TRT paths (a fixed
    // low-discrepancy set in the 4 dimensions of the two interfaces' normals, so that the value is
    // deterministic; Cycles draws one at random per node).
    explicit HuangBcsdf(const HairParams& params, int residual_samples = kDefaultResidualSamples);

    // Lobes R, TT, TRT, TRRT+ of S(wi, wo), far field.
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    // The same with the set of visible normals shifted by `rotation` (each in [0, 1), modulo 1): with a
    // uniformly random rotation each pair of normals (first and second interface) is uniformly and
    // independently distributed, so the value is an unbiased estimate whatever the number of normals
    // (a path tracer's choice: Cycles draws one per node).
    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo, const glm::dvec4& rotation) const;
    // Chiang et al. 2016's shapes of the stand-in Chiang fibre (beta_m): what Zinke's averages use.
    std::span<const LongitudinalLobe> lobe_shapes() const override { return lobes_; }
    std::string_view name() const override { return "huang"; }

    // Draws wi for wo from 11 uniforms in [0, 1): the offset h across the width, one visible normal
    // per interface, the lobe by the energies of the four paths so drawn, and the TRRT+ direction from
    // its longitudinal lobe and a uniform azimuth. weight is 0 when no path leaves towards wi.
    FibreSample sample(const glm::dvec3& wo, const std::array<double, 11>& u) const;

    // Half the fibre's width seen from w (in units of the major semi-axis): sqrt(cos^2 phi + b^2 sin^2 phi).
    double projected_radius(const glm::dvec3& w) const;

    const HairParams& params() const { return params_; }

    static constexpr int kDefaultResidualSamples = 8;

private:
    HairParams params_;
    std::array<LongitudinalLobe, 4> lobes_;
    DielectricEnergyScale energy_scale_;
    int residual_samples_;
};

}  // namespace hairlod::bcsdf
