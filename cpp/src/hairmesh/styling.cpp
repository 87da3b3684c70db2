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
    const float cell = std::floor(x);
    const float f = x - cell, blend = f * f * (3.0f - 2.0f * f);
    const auto i = static_cast<int64_t>(cell);
    return glm::mix(lattice_values(key, i), lattice_values(key, i + 1), blend);
}

uint64_t frizz_key(uint64_t noise_key, size_t operation) { return hash_keys(noise_key, operation, 0x6672); }

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

StrandStyling strand_styling(std::span<const StylingOperation> operations, uint64_t seed, uint64_t strand_key) {
    StrandStyling strand;
    strand.parameters.resize(operations.size(), glm::vec4(0.0f));
    strand.noise_key = hash_keys(seed, strand_key, 0x6e6f);
    for (size_t i = 0; i < operations.size(); ++i) {
        const auto random = [&](uint64_t k) { return random_unit(seed, strand_key, i, k); };
        glm::vec4& p = strand.parameters[i];
        if (const auto* curl = std::get_if<Curl>(&operations[i])) {
            const float phi0 = kTwoPi * curl->randomness * random(2);
            p = {curl->radius * (1.0f + curl->randomness * (random(0) - 0.5f)),
                 curl->frequency * (1.0f + curl->randomness * (random(1) - 0.5f)), phi0, 0.0f};
        } else if (const auto* wave = std::get_if<Wave>(&operations[i])) {
            const float phi0 = kTwoPi * wave->randomness * random(0);
            p = {phi0, std::sin(phi0), 0.0f, 0.0f};
        } else if (std::holds_alternative<Frizz>(operations[i])) {
            p = glm::vec4(value_noise(frizz_key(strand.noise_key, i), 0.0f), 0.0f);
        } else if (const auto* trim = std::get_if<Trim>(&operations[i])) {
            strand.length_fraction *= 1.0f - trim->amount * random(0);
        }
    }
    return strand;
}

void apply_styling(std::span<const StylingOperation> operations, const StrandStyling& strand, StylingVertex& vertex) {
    const float w = vertex.w_from_root;
    for (size_t i = 0; i < operations.size(); ++i) {
        const StylingOperation& op = operations[i];
        const glm::vec4& p = strand.parameters[i];
        if (std::holds_alternative<Curl>(op)) {
            const float phi0 = p.z, phi = phi0 + kTwoPi * p.y * w;
            vertex.position += p.x * ((std::cos(phi) - std::cos(phi0)) * vertex.u + (std::sin(phi) - std::sin(phi0)) * vertex.v);
        } else if (const auto* wave = std::get_if<Wave>(&op)) {
            vertex.position += wave->amplitude * (std::sin(kTwoPi * wave->frequency * w + p.x) - p.y) * vertex.u;
        } else if (const auto* twist = std::get_if<Twist>(&op)) {
            // Rodrigues' rotation of the offset from the centre curve about the unit axis w.
            const float angle = kTwoPi * twist->rate * w;
            const float c = std::cos(angle), s = std::sin(angle);
            const glm::vec3 r = vertex.position - vertex.centre;
            vertex.position = vertex.centre + r * c + glm::cross(vertex.w, r) * s +
                              vertex.w * (glm::dot(vertex.w, r) * (1.0f - c));
        } else if (const auto* clump = std::get_if<Clump>(&op)) {
            const float pull = clump->amount * std::pow(vertex.t, clump->profile);
            vertex.position += pull * (vertex.centre - vertex.position);
        } else if (const auto* frizz = std::get_if<Frizz>(&op)) {
            const glm::vec3 n = value_noise(frizz_key(strand.noise_key, i), frizz->frequency * w) - glm::vec3(p);
            vertex.position += frizz->amplitude * (n.x * vertex.u + n.y * vertex.v + n.z * vertex.w);
        }
    }
}

}  // namespace hairlod
