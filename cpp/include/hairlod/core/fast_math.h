#pragma once
// Branch-free float approximations of sin/cos and powers, written so that loops calling them
// vectorise (libm's calls do not). Styling runs them per generated vertex; none needs more than
// single-precision accuracy. Bounds are stated per function and tested in fast_math_test.cpp.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace hairlod {

struct SinCos {
    float sin, cos;
};

// sin and cos to about 1e-7 absolute beyond the rounding of x itself: Cody-Waite reduction to
// [-pi/4, pi/4] around the nearest multiple of pi/2 (pi/2 split into three floats whose products
// with the quadrant are exact), then Taylor polynomials. Valid for |x| < 2^23 (styling phases).
[[gnu::always_inline]] inline SinCos fast_sin_cos(float x) {
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

// log2(x) for normal x > 0, to 2e-7 absolute plus the float rounding of the result: x = m 2^e with m in [sqrt(1/2), sqrt(2)),
// log2(m) = 2 atanh(s) / ln 2 with s = (m - 1) / (m + 1), |s| <= 0.172, by its odd series to s^9.
[[gnu::always_inline]] inline float fast_log2(float x) {
    // Integer arithmetic only (no branch, so loops vectorise): adding 1 - sqrt(1/2) in the bit
    // pattern carries into the exponent exactly when the mantissa is at least sqrt(2).
    const uint32_t shifted = std::bit_cast<uint32_t>(x) + (0x3F800000u - 0x3F3504F3u);
    const auto exponent = static_cast<float>(static_cast<int32_t>(shifted >> 23) - 127);
    const float m = std::bit_cast<float>((shifted & 0x007FFFFFu) + 0x3F3504F3u);
    const float s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
    const float atanh = s * (1.0f + s2 * (1.0f / 3.0f + s2 * (1.0f / 5.0f + s2 * (1.0f / 7.0f + s2 * (1.0f / 9.0f)))));
    return exponent + 2.88539008f * atanh;  // 2 / ln 2
}

// 2^y to about 2e-7 relative for y in [-126, 127], 0 below -126 (no denormals); y must not be NaN.
// 2^y = 2^n e^(f ln 2) with n = round(y), |f| <= 1/2, the exponential by its Taylor series to f^6.
[[gnu::always_inline]] inline float fast_exp2(float y) {
    // std::min / max, not fmin / fmax: GCC calls those out of line for their NaN rules.
    const float clamped = std::min(std::max(y, -126.0f), 127.0f);
    const auto n = static_cast<int32_t>(clamped + std::copysign(0.5f, clamped));  // round half away
    const auto rounded = static_cast<float>(n);
    const float g = (clamped - rounded) * 0.693147181f;
    const float e = 1.0f + g * (1.0f + g * (0.5f + g * (1.0f / 6.0f + g * (1.0f / 24.0f + g * (1.0f / 120.0f + g * (1.0f / 720.0f))))));
    const float power = e * std::bit_cast<float>(static_cast<uint32_t>(n + 127) << 23);
    return y < -126.0f ? 0.0f : power;
}

// t^p for t in [0, 1] and p > 0, to 1e-6 + 6e-8 |p log2 t| relative (the second term is the
// float rounding of the exponent p log2 t itself); 0^p = 0.
[[gnu::always_inline]] inline float fast_pow_unit(float t, float p) {
    const float power = fast_exp2(p * fast_log2(t));  // evaluated unconditionally: a select vectorises
    return t > 0.0f ? power : 0.0f;
}

}  // namespace hairlod
