#include "hairlod/lod/compact.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

namespace hairlod {

namespace {

constexpr float kLevels = 65535.0f;       // largest 16-bit code
constexpr float kSnorm16 = 32767.0f;
constexpr float kPi = 3.14159265358979f;

// An orthonormal pair spanning the plane normal to the unit `axis`
// (Duff et al. 2017, "Building an orthonormal basis, revisited"); a fixed function of `axis`, which
// is all decoding needs.
void plane_basis(const glm::vec3& axis, glm::vec3& u, glm::vec3& v) {
    const float sign = std::copysign(1.0f, axis.z);
    const float a = -1.0f / (sign + axis.z);
    const float b = axis.x * axis.y * a;
    u = glm::vec3(1.0f + sign * axis.x * axis.x * a, sign * b, -sign * axis.x);
    v = glm::vec3(b, sign + axis.y * axis.y * a, -axis.y);
}

// Octahedral folding of the lower hemisphere onto the outer triangles of the unit square.
glm::vec2 fold(const glm::vec2& p) {
    return (1.0f - glm::abs(glm::vec2(p.y, p.x))) * glm::vec2(p.x >= 0.0f ? 1.0f : -1.0f, p.y >= 0.0f ? 1.0f : -1.0f);
}

}  // namespace

QuantisationBox QuantisationBox::enclosing(std::span<const glm::vec3> points) {
    glm::vec3 lower(std::numeric_limits<float>::infinity()), upper(-std::numeric_limits<float>::infinity());
    for (const glm::vec3& p : points) {
        lower = glm::min(lower, p);
        upper = glm::max(upper, p);
    }
    if (points.empty()) return {};
    return {lower, (upper - lower) / kLevels};
}

glm::u16vec3 QuantisationBox::encode(const glm::vec3& point) const {
    glm::u16vec3 code(0);
    for (int axis = 0; axis < 3; ++axis)
        if (step[axis] > 0.0f)
            code[axis] = static_cast<uint16_t>(std::clamp(std::round((point[axis] - lower[axis]) / step[axis]), 0.0f, kLevels));
    return code;
}

glm::i16vec2 encode_octahedral(const glm::vec3& unit) {
    glm::vec2 p = glm::vec2(unit) / (std::abs(unit.x) + std::abs(unit.y) + std::abs(unit.z));
    if (unit.z < 0.0f) p = fold(p);
    const glm::vec2 scaled = glm::round(glm::clamp(p, -1.0f, 1.0f) * kSnorm16);
    return {static_cast<int16_t>(scaled.x), static_cast<int16_t>(scaled.y)};
}

glm::vec3 decode_octahedral(const glm::i16vec2& code) {
    const glm::vec2 p = glm::vec2(code) / kSnorm16;
    const float z = 1.0f - std::abs(p.x) - std::abs(p.y);
    return glm::normalize(glm::vec3(z < 0.0f ? fold(p) : p, z));
}

uint16_t encode_perpendicular(const glm::vec3& axis, const glm::vec3& perpendicular) {
    glm::vec3 u, v;
    plane_basis(axis, u, v);
    float angle = std::atan2(glm::dot(perpendicular, v), glm::dot(perpendicular, u));
    if (angle < 0.0f) angle += kPi;  // the opposite direction spans the same ellipse axis
    return static_cast<uint16_t>(static_cast<uint32_t>(std::lround(angle / kPi * 65536.0f)) & 0xFFFFu);
}

glm::vec3 decode_perpendicular(const glm::vec3& axis, uint16_t code) {
    glm::vec3 u, v;
    plane_basis(axis, u, v);
    const float angle = static_cast<float>(code) * (kPi / 65536.0f);
    return std::cos(angle) * u + std::sin(angle) * v;
}

uint16_t encode_half_up(float value, int exponent) {
    const float scaled = std::ldexp(value, -exponent);
    uint16_t code = glm::packHalf1x16(scaled);
    if (glm::unpackHalf1x16(code) < scaled) ++code;  // the next half up (positive halves order like integers)
    return code;
}

float decode_half(uint16_t code, int exponent) { return std::ldexp(glm::unpackHalf1x16(code), exponent); }

}  // namespace hairlod
