#include "hairlod/hairmesh/styling.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"
#include "hairlod/core/fast_math.h"
#include "hairlod/core/vector_clones.h"
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

// floor by truncation, corrected below zero (inlined, unlike std::floor without SSE4.1). Clamped
// to +-2^62 first, so huge coordinates and NaN stay defined.
int64_t floor_to_int(float x) {
    auto i = static_cast<int64_t>(!(x >= -4.6e18f) ? -4.6e18f : (x > 4.6e18f ? 4.6e18f : x));
    if (static_cast<float>(i) > x) --i;
    return i;
}

// C1 value noise: lattice values blended with the smoothstep of the cell fraction.
glm::vec3 value_noise(uint64_t key, float x) {
    const int64_t i = floor_to_int(x);
    const float f = x - static_cast<float>(i), blend = f * f * (3.0f - 2.0f * f);
    return glm::mix(lattice_values(key, i), lattice_values(key, i + 1), blend);
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

StylingInputs styling_inputs(std::span<const StylingOperation> operations) {
    StylingInputs in;
    for (const StylingOperation& op : operations) {
        const bool curl = std::holds_alternative<Curl>(op), wave = std::holds_alternative<Wave>(op),
                   twist = std::holds_alternative<Twist>(op), clump = std::holds_alternative<Clump>(op),
                   frizz = std::holds_alternative<Frizz>(op);
        in.u |= curl || wave || frizz;
        in.v |= curl || frizz;
        in.w_axis |= twist || frizz;
        in.centre |= twist || clump;
        in.w_from_root |= curl || wave || twist || frizz;
        in.t |= clump;
    }
    return in;
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

// One function per operation over restrict-qualified component arrays, out of line and cloned for
// AVX2 (core/vector_clones.h) so that the loops vectorise.
HAIRLOD_VECTOR_CLONES void apply_curl(float* __restrict x, float* __restrict y, float* __restrict z,
                                  const float* __restrict ux, const float* __restrict uy, const float* __restrict uz,
                                  const float* __restrict vx, const float* __restrict vy, const float* __restrict vz,
                                  const float* __restrict w, size_t first, size_t n, const OperationConstants c) {
    for (size_t k = first; k < n; ++k) {
        const SinCos phi = fast_sin_cos(c.phase + c.angular_rate * w[k]);
        const float a = c.amplitude * phi.cos - c.at_root.x, b = c.amplitude * phi.sin - c.at_root.y;
        x[k] += a * ux[k] + b * vx[k];
        y[k] += a * uy[k] + b * vy[k];
        z[k] += a * uz[k] + b * vz[k];
    }
}

HAIRLOD_VECTOR_CLONES void apply_wave(float* __restrict x, float* __restrict y, float* __restrict z,
                                  const float* __restrict ux, const float* __restrict uy, const float* __restrict uz,
                                  const float* __restrict w, size_t first, size_t n, const OperationConstants c) {
    for (size_t k = first; k < n; ++k) {
        const float a = c.amplitude * fast_sin_cos(c.angular_rate * w[k] + c.phase).sin - c.at_root.x;
        x[k] += a * ux[k];
        y[k] += a * uy[k];
        z[k] += a * uz[k];
    }
}

// Rodrigues' rotation of the offset r from the centre curve about the unit axis w.
HAIRLOD_VECTOR_CLONES void apply_twist(float* __restrict x, float* __restrict y, float* __restrict z,
                                   const float* __restrict ax, const float* __restrict ay, const float* __restrict az,
                                   const float* __restrict cx, const float* __restrict cy, const float* __restrict cz,
                                   const float* __restrict w, size_t first, size_t n, float angular_rate) {
    for (size_t k = first; k < n; ++k) {
        const SinCos angle = fast_sin_cos(angular_rate * w[k]);
        const float rx = x[k] - cx[k], ry = y[k] - cy[k], rz = z[k] - cz[k];
        const float along = (ax[k] * rx + ay[k] * ry + az[k] * rz) * (1.0f - angle.cos);
        x[k] = cx[k] + rx * angle.cos + (ay[k] * rz - az[k] * ry) * angle.sin + ax[k] * along;
        y[k] = cy[k] + ry * angle.cos + (az[k] * rx - ax[k] * rz) * angle.sin + ay[k] * along;
        z[k] = cz[k] + rz * angle.cos + (ax[k] * ry - ay[k] * rx) * angle.sin + az[k] * along;
    }
}

HAIRLOD_VECTOR_CLONES void apply_clump(float* __restrict x, float* __restrict y, float* __restrict z,
                                   const float* __restrict cx, const float* __restrict cy, const float* __restrict cz,
                                   const float* __restrict pull, size_t first, size_t n, float amount) {
    for (size_t k = first; k < n; ++k) {
        const float weight = amount * pull[k];
        x[k] += weight * (cx[k] - x[k]);
        y[k] += weight * (cy[k] - y[k]);
        z[k] += weight * (cz[k] - z[k]);
    }
}

// t^profile at vertices [first, n) for clump operation `index`, recomputed only when t or the
// profile differ from the previous strand's (indices below `first` are left unset).
const float* clump_pull(StrandStyling& strand, size_t index, const float* t, size_t first, size_t n, float profile) {
    if (strand.clump_pulls.size() <= index) strand.clump_pulls.resize(index + 1);
    StrandStyling::ClumpPull& cache = strand.clump_pulls[index];
    if (cache.profile == profile && cache.t.size() == n && std::equal(t + first, t + n, cache.t.begin() + first))
        return cache.pull.data();
    cache.profile = profile;
    cache.t.assign(t, t + n);
    cache.pull.resize(n);
    for (size_t k = first; k < n; ++k) cache.pull[k] = fast_pow_unit(t[k], profile);
    return cache.pull.data();
}

// Largest |frequency w| the lattice path takes: cells are then exact int32 values.
constexpr float kLatticeReach = 1073741824.0f;  // 2^30

// Frizz offsets n(frequency w) from the lattice values of cells first_cell .. first_cell + last + 1
// (value_noise with the hashing done beforehand, the table stored component by component),
// moved along the frame. A plain loop with int32 cell indices: the AVX2 clone vectorises it with
// gathers from the table.
HAIRLOD_VECTOR_CLONES void apply_frizz_lattice(
    float* __restrict x, float* __restrict y, float* __restrict z, const float* __restrict ux,
    const float* __restrict uy, const float* __restrict uz, const float* __restrict vx, const float* __restrict vy,
    const float* __restrict vz, const float* __restrict wx, const float* __restrict wy, const float* __restrict wz,
    const float* __restrict w, size_t first, size_t n, const float* __restrict lattice_x,
    const float* __restrict lattice_y, const float* __restrict lattice_z, int32_t first_cell, int32_t last,
    float frequency, float amplitude, glm::vec3 at_root) {
    for (size_t k = first; k < n; ++k) {
        const float cell_x = frequency * w[k];
        const float reach = std::min(std::max(cell_x, -kLatticeReach), kLatticeReach);
        auto cell = static_cast<int32_t>(reach);
        cell -= static_cast<float>(cell) > reach ? 1 : 0;  // floor, as floor_to_int
        const float f = cell_x - static_cast<float>(cell), blend = f * f * (3.0f - 2.0f * f);
        const int32_t i = std::min(std::max(cell - first_cell, 0), last);
        // glm::mix's form, as value_noise.
        const float nx = amplitude * (lattice_x[i] * (1.0f - blend) + lattice_x[i + 1] * blend) - at_root.x;
        const float ny = amplitude * (lattice_y[i] * (1.0f - blend) + lattice_y[i + 1] * blend) - at_root.y;
        const float nz = amplitude * (lattice_z[i] * (1.0f - blend) + lattice_z[i + 1] * blend) - at_root.z;
        x[k] = x[k] + nx * ux[k] + ny * vx[k] + nz * wx[k];
        y[k] = y[k] + nx * uy[k] + ny * vy[k] + nz * wy[k];
        z[k] = z[k] + nx * uz[k] + ny * vz[k] + nz * wz[k];
    }
}

// The lattice values are hashed once per cell the strand spans, not twice per vertex; a strand
// spanning more than two cells per vertex (noise far finer than its vertices) hashes per vertex
// instead. Both give value_noise's offsets.
void apply_frizz(StrandVertices& v, size_t first, const Frizz& frizz, const OperationConstants& c,
                 std::vector<float>& lattice) {
    using V = StrandVertices;
    const float* w = v[V::W_FROM_ROOT];
    float low = INFINITY, high = -INFINITY;
    for (size_t k = first; k < v.size(); ++k) {
        low = frizz.frequency * w[k] < low ? frizz.frequency * w[k] : low;
        high = frizz.frequency * w[k] > high ? frizz.frequency * w[k] : high;
    }
    if (!(high - low <= 2.0f * static_cast<float>(v.size()) && low > -kLatticeReach && high < kLatticeReach)) {  // also NaN
        for (size_t k = first; k < v.size(); ++k) {
            const glm::vec3 n = frizz.amplitude * value_noise(c.noise_key, frizz.frequency * w[k]) - c.at_root;
            v.set_vec3(V::X, k, v.vec3(V::X, k) + n.x * v.vec3(V::UX, k) + n.y * v.vec3(V::VX, k) + n.z * v.vec3(V::WX, k));
        }
        return;
    }
    const int64_t first_cell = floor_to_int(low);
    const auto cells = static_cast<size_t>(floor_to_int(high) - first_cell + 2);
    lattice.resize(3 * cells);  // x values, then y, then z
    for (size_t i = 0; i < cells; ++i) {
        const glm::vec3 value = lattice_values(c.noise_key, first_cell + static_cast<int64_t>(i));
        lattice[i] = value.x;
        lattice[cells + i] = value.y;
        lattice[2 * cells + i] = value.z;
    }
    apply_frizz_lattice(v[V::X], v[V::Y], v[V::Z], v[V::UX], v[V::UY], v[V::UZ], v[V::VX], v[V::VY], v[V::VZ], v[V::WX],
                        v[V::WY], v[V::WZ], w, first, v.size(), lattice.data(), lattice.data() + cells,
                        lattice.data() + 2 * cells, static_cast<int32_t>(first_cell), static_cast<int32_t>(cells) - 2,
                        frizz.frequency, frizz.amplitude, c.at_root);
}

}  // namespace

void apply_styling(std::span<const StylingOperation> operations, StrandStyling& strand, StrandVertices& vertices,
                   size_t first) {
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
            apply_clump(v[V::X], v[V::Y], v[V::Z], v[V::CX], v[V::CY], v[V::CZ],
                        clump_pull(strand, i, v[V::T], first, n, clump->profile), first, n, clump->amount);
        else if (const auto* frizz = std::get_if<Frizz>(&op))
            apply_frizz(v, first, *frizz, c, strand.noise_lattice);
    }
}

}  // namespace hairlod
