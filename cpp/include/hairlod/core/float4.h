#pragma once
// Four floats in one SSE register, through the GCC / Clang vector extension: for loops whose blocks
// the auto-vectoriser will not form itself (short runs, gathers from small tables). Arithmetic
// operators work lane by lane and mix with scalars.
#include <cmath>
#include <cstdint>
#include <cstring>

namespace hairlod {

typedef float Float4 __attribute__((vector_size(16)));
typedef int32_t Int4 __attribute__((vector_size(16)));  // comparisons of Float4 give all-ones / zero lanes

inline Float4 load4(const float* from) {
    Float4 value;
    std::memcpy(&value, from, sizeof value);
    return value;
}

inline void store4(float* to, Float4 value) { std::memcpy(to, &value, sizeof value); }

// Square root lane by lane (correctly rounded, as std::sqrt).
inline Float4 sqrt4(Float4 value) {
#if defined(__SSE__)
    return __builtin_ia32_sqrtps(value);
#else
    return Float4{std::sqrt(value[0]), std::sqrt(value[1]), std::sqrt(value[2]), std::sqrt(value[3])};
#endif
}

// Lanes of `if_true` where `mask` is set, else 0.
inline Float4 where4(Int4 mask, Float4 if_true) {
    return reinterpret_cast<Float4>(reinterpret_cast<Int4>(if_true) & mask);
}

// Writes 4 points given as x, y, z lanes as 12 interleaved floats x0 y0 z0 x1 ... z3 (an array of
// vec3) with three vector stores.
inline void store_interleaved4(float* to, Float4 x, Float4 y, Float4 z) {
    const Float4 xy_low = __builtin_shufflevector(x, y, 0, 4, 1, 5);   // x0 y0 x1 y1
    const Float4 xy_high = __builtin_shufflevector(x, y, 2, 6, 3, 7);  // x2 y2 x3 y3
    const Float4 yz_1 = __builtin_shufflevector(xy_low, z, 3, 5, 3, 5);  // y1 z1 . .
    store4(to, __builtin_shufflevector(xy_low, z, 0, 1, 4, 2));          // x0 y0 z0 x1
    store4(to + 4, __builtin_shufflevector(yz_1, xy_high, 0, 1, 4, 5));  // y1 z1 x2 y2
    store4(to + 8, __builtin_shufflevector(z, xy_high, 2, 6, 7, 3));     // z2 x3 y3 z3
}

}  // namespace hairlod
