#pragma once
// Compact encodings of the LoD asset's per-control-point data, each with a stated error bound.
#include <cstdint>
#include <span>

#include <glm/vec3.hpp>
#include <glm/gtc/type_precision.hpp>

namespace hairlod {

// 16-bit fixed point per coordinate inside an axis-aligned box: a coordinate decodes within
// step / 2 of its value (step = box extent / 65535 per axis).
struct QuantisationBox {
    glm::vec3 lower{0.0f};
    glm::vec3 step{0.0f};

    static QuantisationBox enclosing(std::span<const glm::vec3> points);
    glm::u16vec3 encode(const glm::vec3& point) const;
    glm::vec3 decode(const glm::u16vec3& code) const { return lower + step * glm::vec3(code); }
};

// Unit vector in octahedral encoding (Meyer et al. 2010, "On floating-point normal vectors"),
// two signed 16-bit components: below 1e-4 rad of angular error.
glm::i16vec2 encode_octahedral(const glm::vec3& unit);
glm::vec3 decode_octahedral(const glm::i16vec2& code);

// A unit vector perpendicular to `axis` (unit), as the angle in [0, pi) from a basis of the plane
// normal to `axis` in 16 bits (pi / 65536 rad steps): an ellipse axis, so its sign is free.
uint16_t encode_perpendicular(const glm::vec3& axis, const glm::vec3& perpendicular);
glm::vec3 decode_perpendicular(const glm::vec3& axis, uint16_t code);

// A value >= 0, scaled by 2^-exponent (exact), as an IEEE half float rounded up: it decodes to at
// least the value and, in the half's normal range (scaled values >= 2^-14), at most 2^-10 of it above.
uint16_t encode_half_up(float value, int exponent);
float decode_half(uint16_t code, int exponent);

}  // namespace hairlod
