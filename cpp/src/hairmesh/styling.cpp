#include "hairlod/hairmesh/styling.h"

#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairlod/hairmesh/hash_random.h"

namespace hairlod {

namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

// Three lattice values in [-1, 1] of the value noise at integer cell `cell`, from one hash.
glm::vec3 lattice_values(uint64_t key, int64_t cell) {
    const uint64_t bits = mix64(key ^ (static_cast<uint64_t>(cell) * 0xD1B54A32D192ED03ull));
    constexpr float scale = 2.0f / static_cast<float>(1u << 21);
    return glm::vec3(static_cast<float>(bits & 0x1FFFFF), static_cast<float>((bits >> 21) & 0x1FFFFF),
                     static_cast<float>((bits >> 42) & 0x1FFFFF)) * scale - 1.0f;
}

// C1 value noise: lattice values blended with the smoothstep of the cell fraction.
glm::vec3 value_noise(uint64_t key, float x) {
    // floor by truncation, corrected below zero (inlined, unlike std::floor without SSE4.1).
    auto i = static_cast<int64_t>(x);
    if (static_cast<float>(i) > x) --i;
    const float f = x - static_cast<float>(i), blend = f * f * (3.0f - 2.0f * f);
    return glm::mix(lattice_values(key, i), lattice_values(key, i + 1), blend);
}

struct SinCos {
    float sin, cos;
};

// sin and cos to about 1e-7 absolute for |x| up to 1e4: reduction to [-pi/4, pi/4] around the
// nearest multiple of pi/2, then Taylor polynomials; 3-4x faster than sinf + cosf, and styling
// phases need no more accuracy.
[[gnu::always_inline]] inline SinCos sin_cos(float x) {
    constexpr double kHalfPi = std::numbers::pi / 2.0, kInverseHalfPi = 2.0 / std::numbers::pi;
    // Round to nearest by truncation (inlined, unlike nearbyint without SSE4.1).
    const double y = static_cast<double>(x) * kInverseHalfPi;
    const auto quadrant = static_cast<int64_t>(y + (y >= 0.0 ? 0.5 : -0.5));
    const auto f = static_cast<float>(static_cast<double>(x) - static_cast<double>(quadrant) * kHalfPi);
    const float f2 = f * f;
    const float s = f * (1.0f + f2 * (-1.0f / 6.0f + f2 * (1.0f / 120.0f + f2 * (-1.0f / 5040.0f + f2 * (1.0f / 362880.0f)))));
    const float c = 1.0f + f2 * (-0.5f + f2 * (1.0f / 24.0f + f2 * (-1.0f / 720.0f + f2 * (1.0f / 40320.0f))));
    // Quadrant q: odd q swaps sin and cos; sin is negative for q = 2, 3, cos for q = 1, 2.
    const int64_t q = quadrant & 3;
    const float sin_sign = (q & 2) ? -1.0f : 1.0f, cos_sign = ((q + 1) & 2) ? -1.0f : 1.0f;
    return (q & 1) ? SinCos{sin_sign * c, cos_sign * s} : SinCos{sin_sign * s, cos_sign * c};
}

void require(bool ok, size_t index, const char* operation, const char* message) {
    if (!ok) throw Error("styling operation " + std::to_string(index) + " (" + operation + "): " + message);
}

bool finite_all(std::initializer_list<float> values) {
    for (float value : values)
        if (!std::isfinite(value)) return false;
    return true;
}

}  // namespace

void validate_styling(std::span<const StylingOperation> operations) {
    for (size_t i = 0; i < operations.size(); ++i) {
        const StylingOperation& op = operations[i];
        if (const auto* curl = std::get_if<Curl>(&op)) {
            require(finite_all({curl->radius, curl->frequency, curl->randomness}), i, "curl", "parameters must be finite");
            require(curl->radius >= 0.0f, i, "curl", "radius must be >= 0");
            require(curl->randomness >= 0.0f && curl->randomness <= 1.0f, i, "curl", "randomness must be in [0, 1]");
        } else if (const auto* wave = std::get_if<Wave>(&op)) {
            require(finite_all({wave->amplitude, wave->frequency, wave->randomness}), i, "wave", "parameters must be finite");
            require(wave->randomness >= 0.0f && wave->randomness <= 1.0f, i, "wave", "randomness must be in [0, 1]");
        } else if (const auto* twist = std::get_if<Twist>(&op)) {
            require(std::isfinite(twist->rate), i, "twist", "rate must be finite");
        } else if (const auto* clump = std::get_if<Clump>(&op)) {
            require(finite_all({clump->amount, clump->profile}), i, "clump", "parameters must be finite");
            require(clump->amount >= 0.0f && clump->amount <= 1.0f, i, "clump", "amount must be in [0, 1]");
            require(clump->profile > 0.0f, i, "clump", "profile must be > 0 (the root must not move)");
        } else if (const auto* frizz = std::get_if<Frizz>(&op)) {
            require(finite_all({frizz->amplitude, frizz->frequency}), i, "frizz", "parameters must be finite");
            require(frizz->frequency >= 0.0f, i, "frizz", "frequency must be >= 0");
        } else if (const auto* trim = std::get_if<Trim>(&op)) {
            require(std::isfinite(trim->amount) && trim->amount >= 0.0f && trim->amount <= 1.0f, i, "trim",
                    "amount must be in [0, 1]");
        }
    }
}

void draw_strand_styling(std::span<const StylingOperation> operations, uint64_t seed, uint64_t strand_key,
                         StrandStyling& strand) {
    strand.operations.assign(operations.size(), OperationConstants{});
    strand.length_fraction = 1.0f;
    for (size_t i = 0; i < operations.size(); ++i) {
        const auto random = [&](uint64_t k) { return random_unit(seed, strand_key, i, k); };
        OperationConstants& constants = strand.operations[i];
        if (const auto* curl = std::get_if<Curl>(&operations[i])) {
            constants.amplitude = curl->radius * (1.0f + curl->randomness * (random(0) - 0.5f));
            constants.angular_rate = kTwoPi * curl->frequency * (1.0f + curl->randomness * (random(1) - 0.5f));
            constants.phase = kTwoPi * curl->randomness * random(2);
            constants.at_root = constants.amplitude * glm::vec3(std::cos(constants.phase), std::sin(constants.phase), 0.0f);
        } else if (const auto* wave = std::get_if<Wave>(&operations[i])) {
            constants.amplitude = wave->amplitude;
            constants.angular_rate = kTwoPi * wave->frequency;
            constants.phase = kTwoPi * wave->randomness * random(0);
            constants.at_root.x = wave->amplitude * std::sin(constants.phase);
        } else if (const auto* frizz = std::get_if<Frizz>(&operations[i])) {
            constants.noise_key = hash_keys(seed, strand_key, i, 0x6672);
            constants.at_root = frizz->amplitude * value_noise(constants.noise_key, 0.0f);
        } else if (const auto* trim = std::get_if<Trim>(&operations[i])) {
            strand.length_fraction *= 1.0f - trim->amount * random(0);
        }
    }
}

void apply_styling(std::span<const StylingOperation> operations, const StrandStyling& strand,
                   std::span<StylingVertex> vertices) {
    for (size_t i = 0; i < operations.size(); ++i) {
        const StylingOperation& op = operations[i];
        const OperationConstants& constants = strand.operations[i];
        if (std::holds_alternative<Curl>(op)) {
            for (StylingVertex& vertex : vertices) {
                const SinCos phi = sin_cos(constants.phase + constants.angular_rate * vertex.w_from_root);
                vertex.position += (constants.amplitude * phi.cos - constants.at_root.x) * vertex.u +
                                   (constants.amplitude * phi.sin - constants.at_root.y) * vertex.v;
            }
        } else if (std::holds_alternative<Wave>(op)) {
            for (StylingVertex& vertex : vertices) {
                const float wave = constants.amplitude * sin_cos(constants.angular_rate * vertex.w_from_root + constants.phase).sin;
                vertex.position += (wave - constants.at_root.x) * vertex.u;
            }
        } else if (const auto* twist = std::get_if<Twist>(&op)) {
            for (StylingVertex& vertex : vertices) {
                // Rodrigues' rotation of the offset from the centre curve about the unit axis w.
                const SinCos angle = sin_cos(kTwoPi * twist->rate * vertex.w_from_root);
                const glm::vec3 r = vertex.position - vertex.centre;
                vertex.position = vertex.centre + r * angle.cos + glm::cross(vertex.w, r) * angle.sin +
                                  vertex.w * (glm::dot(vertex.w, r) * (1.0f - angle.cos));
            }
        } else if (const auto* clump = std::get_if<Clump>(&op)) {
            for (StylingVertex& vertex : vertices) {
                // t^profile through exp2 / log2: half the cost of powf; t = 0 gives exp2(-inf) = 0.
                const float pull = clump->amount * std::exp2(clump->profile * std::log2(vertex.t));
                vertex.position += pull * (vertex.centre - vertex.position);
            }
        } else if (const auto* frizz = std::get_if<Frizz>(&op)) {
            for (StylingVertex& vertex : vertices) {
                const glm::vec3 n = frizz->amplitude * value_noise(constants.noise_key, frizz->frequency * vertex.w_from_root) -
                                    constants.at_root;
                vertex.position += n.x * vertex.u + n.y * vertex.v + n.z * vertex.w;
            }
        }
    }
}

}  // namespace hairlod
