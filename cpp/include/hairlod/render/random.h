#pragma once
// Counter-based random numbers for the renderers: every (seed, pixel, sample) starts its own stream,
// so an image does not depend on how TBB schedules tiles (deterministic per seed).
#include <cstdint>

namespace hairlod::render {

// SplitMix64 finaliser (Steele et al. 2014): a bijective mix of 64 bits.
inline uint64_t mix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

class Random {
public:
    Random(uint64_t seed, uint64_t pixel, uint64_t sample) : state_(mix64(seed ^ mix64(pixel ^ mix64(sample)))) {}
    // Uniform in [0, 1).
    double uniform() {
        state_ += 0x9e3779b97f4a7c15ull;
        return static_cast<double>(mix64(state_) >> 11) * 0x1.0p-53;
    }

private:
    uint64_t state_;
};

}  // namespace hairlod::render
