#pragma once
// FiberBcsdf: the interface every single-fibre scattering model implements, and batched evaluation.
//
// A value S follows docs/ARCHITECTURE.md ("BCSDF measure"): L_o(w_o) = integral of L_i(w_i) S(w_i, w_o) cos(theta_i) dw_i, with
// theta_i the angle between w_i and the fibre's normal plane, so a lossless, energy-conserving fibre
// has integral of S cos(theta_i) dw_i = 1 (white furnace). Directions are in the fibre frame with the
// tangent along +x and need not be normalised.
#include <array>
#include <span>
#include <string_view>

#include <glm/vec3.hpp>

#include "hairlod/bcsdf/hair_params.h"

namespace hairlod::bcsdf {

inline constexpr int kMaxLobes = 4;

// The value of each lobe of a model (R, TT, TRT, ... in the model's order); `count` are used.
struct LobeValues {
    std::array<glm::dvec3, kMaxLobes> value{};
    int count = 0;
    glm::dvec3 sum() const;
    // Lobe-wise arithmetic, so that quadrature rules integrate all lobes at once.
    LobeValues& operator+=(const LobeValues& other);
    LobeValues& operator-=(const LobeValues& other);
    friend LobeValues operator+(LobeValues a, const LobeValues& b) { return a += b; }
    friend LobeValues operator-(LobeValues a, const LobeValues& b) { return a -= b; }
    friend LobeValues operator*(double w, LobeValues a);
};

// Largest absolute channel of any lobe (the error norm of quadrature over LobeValues).
double magnitude(const LobeValues& lobes);

// Which lobes scatter forward (through the fibre) in the dual-scattering sense is decided by the
// outgoing hemisphere, not by the lobe; each lobe still has a longitudinal shape for Zinke's averages.
class FiberBcsdf {
public:
    virtual ~FiberBcsdf() = default;
    virtual LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const = 0;
    // Longitudinal shift and variance of each lobe (same order and count as eval_lobes).
    virtual std::span<const LongitudinalLobe> lobe_shapes() const = 0;
    virtual std::string_view name() const = 0;
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const { return eval_lobes(wi, wo).sum(); }
};

// out[k] = S(wi[k], wo[k]) (RGB); spans must have equal sizes. Batches are split over TBB threads.
void evaluate(const FiberBcsdf& bcsdf, std::span<const glm::vec3> wi, std::span<const glm::vec3> wo,
              std::span<glm::vec3> out);

}  // namespace hairlod::bcsdf
