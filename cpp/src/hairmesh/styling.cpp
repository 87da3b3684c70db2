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

// sin and cos to about 1e-7 absolute beyond the rounding of x itself: Cody-Waite reduction to
// [-pi/4, pi/4] around the nearest multiple of pi/2 (pi/2 split into three floats whose products
// with the quadrant are exact), then Taylor polynomials. Branch-free float and int32 arithmetic,
// so the styling loops vectorise; styling phases need no more accuracy.
[[gnu::always_inline]] inline SinCos sin_cos(float x) {
    constexpr float kInverseHalfPi = 0.63661977236758134f;
    constexpr float kHalfPiHigh = 1.5703125f, kHalfPiMid = 4.837512969970703125e-4f, kHalfPiLow = 7.54978995489188216e-8f;
    const float y = x * kInverseHalfPi;
    const auto quadrant = static_cast<int32_t>(y + std::copysign(0.5f, y));
    const auto q = static_cast<float>(quadrant);
    const float f = ((x - q * kHalfPiHigh) - q * kHalfPiMid) - q * kHalfPiLow;
    const float f2 = f * f;
    const float s = f * (1.0f + f2 * (-1.0f / 6.0f + f2 * (1.0f / 120.0f + f2 * (-1.0f / 5040.0f + f2 * (1.0f / 362880.0f)))));
    const float c = 1.0f + f2 * (-0.5f + f2 * (1.0f / 24.0f + f2 * (-1.0f / 720.0f + f2 * (1.0f / 40320.0f))));
    // Odd quadrants swap sin and cos; sin is negative in quadrants 2, 3 and cos in 1, 2.
    const auto swap = static_cast<float>(quadrant & 1);
    const auto sin_sign = static_cast<float>(1 - (quadrant & 2)), cos_sign = static_cast<float>(1 - ((quadrant + 1) & 2));
    return {sin_sign * (s + swap * (c - s)), cos_sign * (c + swap * (s - c))};
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

namespace {

// One function per operation over restrict-qualified component arrays: kept out of line so the
// compiler keeps the no-aliasing facts and vectorises the loops.
[[gnu::noinline]] void apply_curl(float* __restrict x, float* __restrict y, float* __restrict z,
                                  const float* __restrict ux, const float* __restrict uy, const float* __restrict uz,
                                  const float* __restrict vx, const float* __restrict vy, const float* __restrict vz,
                                  const float* __restrict w, size_t first, size_t n, const OperationConstants c) {
    for (size_t k = first; k < n; ++k) {
        const SinCos phi = sin_cos(c.phase + c.angular_rate * w[k]);
        const float a = c.amplitude * phi.cos - c.at_root.x, b = c.amplitude * phi.sin - c.at_root.y;
        x[k] += a * ux[k] + b * vx[k];
        y[k] += a * uy[k] + b * vy[k];
        z[k] += a * uz[k] + b * vz[k];
    }
}

[[gnu::noinline]] void apply_wave(float* __restrict x, float* __restrict y, float* __restrict z,
                                  const float* __restrict ux, const float* __restrict uy, const float* __restrict uz,
                                  const float* __restrict w, size_t first, size_t n, const OperationConstants c) {
    for (size_t k = first; k < n; ++k) {
        const float a = c.amplitude * sin_cos(c.angular_rate * w[k] + c.phase).sin - c.at_root.x;
        x[k] += a * ux[k];
        y[k] += a * uy[k];
        z[k] += a * uz[k];
    }
}

// Rodrigues' rotation of the offset r from the centre curve about the unit axis w.
[[gnu::noinline]] void apply_twist(float* __restrict x, float* __restrict y, float* __restrict z,
                                   const float* __restrict ax, const float* __restrict ay, const float* __restrict az,
                                   const float* __restrict cx, const float* __restrict cy, const float* __restrict cz,
                                   const float* __restrict w, size_t first, size_t n, float angular_rate) {
    for (size_t k = first; k < n; ++k) {
        const SinCos angle = sin_cos(angular_rate * w[k]);
        const float rx = x[k] - cx[k], ry = y[k] - cy[k], rz = z[k] - cz[k];
        const float along = (ax[k] * rx + ay[k] * ry + az[k] * rz) * (1.0f - angle.cos);
        x[k] = cx[k] + rx * angle.cos + (ay[k] * rz - az[k] * ry) * angle.sin + ax[k] * along;
        y[k] = cy[k] + ry * angle.cos + (az[k] * rx - ax[k] * rz) * angle.sin + ay[k] * along;
        z[k] = cz[k] + rz * angle.cos + (ax[k] * ry - ay[k] * rx) * angle.sin + az[k] * along;
    }
}

[[gnu::noinline]] void apply_clump(float* __restrict x, float* __restrict y, float* __restrict z,
                                   const float* __restrict cx, const float* __restrict cy, const float* __restrict cz,
                                   const float* __restrict t, size_t first, size_t n, float amount, float profile) {
    for (size_t k = first; k < n; ++k) {
        // t^profile through exp2 / log2: half the cost of powf; t = 0 gives exp2(-inf) = 0.
        const float pull = amount * std::exp2(profile * std::log2(t[k]));
        x[k] += pull * (cx[k] - x[k]);
        y[k] += pull * (cy[k] - y[k]);
        z[k] += pull * (cz[k] - z[k]);
    }
}

void apply_frizz(StrandVertices& v, size_t first, const Frizz& frizz, const OperationConstants& c) {
    using V = StrandVertices;
    for (size_t k = first; k < v.size(); ++k) {
        const glm::vec3 n = frizz.amplitude * value_noise(c.noise_key, frizz.frequency * v[V::W_FROM_ROOT][k]) - c.at_root;
        v.set_vec3(V::X, k, v.vec3(V::X, k) + n.x * v.vec3(V::UX, k) + n.y * v.vec3(V::VX, k) + n.z * v.vec3(V::WX, k));
    }
}

}  // namespace

void apply_styling(std::span<const StylingOperation> operations, const StrandStyling& strand,
                   StrandVertices& vertices, size_t first) {
    using V = StrandVertices;
    V& v = vertices;
    const size_t n = v.size();
    for (size_t i = 0; i < operations.size(); ++i) {
        const StylingOperation& op = operations[i];
        const OperationConstants& c = strand.operations[i];
        if (std::holds_alternative<Curl>(op))
            apply_curl(v[V::X], v[V::Y], v[V::Z], v[V::UX], v[V::UY], v[V::UZ], v[V::VX], v[V::VY], v[V::VZ],
                       v[V::W_FROM_ROOT], first, n, c);
        else if (std::holds_alternative<Wave>(op))
            apply_wave(v[V::X], v[V::Y], v[V::Z], v[V::UX], v[V::UY], v[V::UZ], v[V::W_FROM_ROOT], first, n, c);
        else if (const auto* twist = std::get_if<Twist>(&op))
            apply_twist(v[V::X], v[V::Y], v[V::Z], v[V::WX], v[V::WY], v[V::WZ], v[V::CX], v[V::CY], v[V::CZ],
                        v[V::W_FROM_ROOT], first, n, kTwoPi * twist->rate);
        else if (const auto* clump = std::get_if<Clump>(&op))
            apply_clump(v[V::X], v[V::Y], v[V::Z], v[V::CX], v[V::CY], v[V::CZ], v[V::T], first, n, clump->amount,
                        clump->profile);
        else if (const auto* frizz = std::get_if<Frizz>(&op))
            apply_frizz(v, first, *frizz, c);
    }
}

}  // namespace hairlod
