#pragma once
// Counter-based random numbers: a value is a pure function of (seed, keys), so results do not depend
// on thread scheduling or on the order in which strands are generated.
#include <cstdint>

namespace hairlod {

// SplitMix64 finaliser: a bijective 64-bit mix with full avalanche.
constexpr uint64_t mix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

constexpr uint64_t hash_keys(uint64_t seed, uint64_t a, uint64_t b = 0, uint64_t c = 0) {
    return mix64(mix64(mix64(seed ^ mix64(a)) ^ b) ^ c);
}

// Uniform in [0, 1) from the top 24 bits, so the float is exact and never rounds up to 1.
constexpr float unit_float(uint64_t bits) { return static_cast<float>(bits >> 40) * 0x1.0p-24f; }

constexpr float random_unit(uint64_t seed, uint64_t a, uint64_t b = 0, uint64_t c = 0) {
    return unit_float(hash_keys(seed, a, b, c));
}

// A sequential stream for loops that draw many numbers from one key (sample candidates).
class RandomStream {
public:
    explicit RandomStream(uint64_t seed) : state_(seed) {}
    uint64_t next_bits() { return mix64(state_++); }
    float next_unit() { return unit_float(next_bits()); }

private:
    uint64_t state_;
};

}  // namespace hairlod
