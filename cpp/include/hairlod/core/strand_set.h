#pragma once
// StrandSet: a set of hair strands as a structure of arrays, the data every module shares.
// Curve c owns points [offsets[c], offsets[c+1]); offsets[0] = 0 and offsets is strictly
// increasing with at least 2 points per curve (checked by validate()).
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <glm/vec3.hpp>

namespace hairlod {

static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "points must be tightly packed float[3]");

// Points (a vector or span of glm::vec3) as 3N contiguous floats, for bulk copies; empty, not a
// member access through a null pointer, when there are no points.
template <typename Points>
auto point_floats(Points&& points) {
    using Float = std::conditional_t<std::is_const_v<std::remove_pointer_t<decltype(std::data(points))>>,
                                     const float, float>;
    return std::span<Float>(reinterpret_cast<Float*>(std::data(points)), 3 * std::size(points));
}

enum class AttributeDomain { Point, Curve };

// A named float attribute with `components` floats per point or per curve.
struct Attribute {
    AttributeDomain domain = AttributeDomain::Point;
    int components = 1;
    std::vector<float> values;
};

struct StrandSet {
    std::vector<glm::vec3> points;
    std::vector<int64_t> offsets{0};
    std::vector<float> radius;  // one per point
    std::map<std::string, Attribute, std::less<>> attributes;

    size_t curve_count() const { return offsets.size() - 1; }
    size_t point_count() const { return points.size(); }
    size_t curve_size(size_t curve) const {
        return static_cast<size_t>(offsets[curve + 1] - offsets[curve]);
    }
    std::span<const glm::vec3> curve_points(size_t curve) const {
        return {points.data() + offsets[curve], curve_size(curve)};
    }

    // Appends one curve; `curve_radius` may be empty (radius 0 is then stored).
    void add_curve(std::span<const glm::vec3> curve, std::span<const float> curve_radius = {});

    // Adds or replaces an attribute; throws Error if the value count does not match the domain.
    void set_attribute(const std::string& name, AttributeDomain domain, int components,
                       std::vector<float> values);
    const Attribute* find_attribute(std::string_view name) const;

    // Throws Error naming the first problem: sizes, offsets, NaN/Inf, negative radius.
    void validate() const;

    // Throws Error ("`what`: ...") when the hair is too large or too small for float32 geometry:
    // a coordinate or radius beyond kMaxCoordinate (squared lengths would overflow), or a bounding
    // box diagonal in (0, kMinExtent) (squared spreads would underflow, thick-hair radii become 0).
    // Every computation that resamples, clusters or renders strands calls it first, so extreme
    // inputs are refused with this message instead of coming out NaN.
    void require_float_range(std::string_view what) const;
};

inline constexpr float kMaxCoordinate = 1e13f;  // measured: renders match scale 1 up to 1e14, nothing at 1e15
inline constexpr float kMinExtent = 1e-10f;  // measured: renders match scale 1 down to 1e-11 across

// Builds a StrandSet from points and per-curve point counts; validates it.
StrandSet strands_from_counts(std::vector<glm::vec3> points, std::span<const int64_t> counts,
                              std::vector<float> radius);

}  // namespace hairlod
