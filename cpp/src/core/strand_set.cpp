#include "hairlod/core/strand_set.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "hairlod/core/error.h"

namespace hairlod {

namespace {

std::string domain_name(AttributeDomain domain) {
    return domain == AttributeDomain::Point ? "point" : "curve";
}

size_t domain_size(const StrandSet& strands, AttributeDomain domain) {
    return domain == AttributeDomain::Point ? strands.point_count() : strands.curve_count();
}

}  // namespace

void StrandSet::add_curve(std::span<const glm::vec3> curve, std::span<const float> curve_radius) {
    if (!curve_radius.empty() && curve_radius.size() != curve.size())
        throw Error("add_curve: " + std::to_string(curve.size()) + " points but " +
                    std::to_string(curve_radius.size()) + " radii");
    points.insert(points.end(), curve.begin(), curve.end());
    if (curve_radius.empty())
        radius.resize(radius.size() + curve.size(), 0.0f);
    else
        radius.insert(radius.end(), curve_radius.begin(), curve_radius.end());
    offsets.push_back(static_cast<int64_t>(points.size()));
}

void StrandSet::set_attribute(const std::string& name, AttributeDomain domain, int components,
                              std::vector<float> values) {
    if (name.empty()) throw Error("attribute name must not be empty");
    if (components < 1) throw Error("attribute '" + name + "': components must be >= 1");
    const size_t expected = domain_size(*this, domain) * static_cast<size_t>(components);
    if (values.size() != expected)
        throw Error("attribute '" + name + "': " + domain_name(domain) + " attribute with " +
                    std::to_string(components) + " components needs " + std::to_string(expected) +
                    " values, got " + std::to_string(values.size()));
    attributes[name] = Attribute{domain, components, std::move(values)};
}

const Attribute* StrandSet::find_attribute(std::string_view name) const {
    auto it = attributes.find(name);
    return it == attributes.end() ? nullptr : &it->second;
}

void StrandSet::validate() const {
    if (offsets.empty() || offsets.front() != 0) throw Error("offsets must start with 0");
    for (size_t c = 0; c + 1 < offsets.size(); ++c) {
        const int64_t count = offsets[c + 1] - offsets[c];
        if (count <= 0)
            throw Error("offsets must be strictly increasing: offsets[" + std::to_string(c + 1) +
                        "] = " + std::to_string(offsets[c + 1]) + " <= offsets[" +
                        std::to_string(c) + "] = " + std::to_string(offsets[c]));
        if (count < 2)
            throw Error("curve " + std::to_string(c) +
                        " has 1 point; every curve needs at least 2");
    }
    if (static_cast<size_t>(offsets.back()) != points.size())
        throw Error("offsets end at " + std::to_string(offsets.back()) + " but there are " +
                    std::to_string(points.size()) + " points");
    if (radius.size() != points.size())
        throw Error("radius has " + std::to_string(radius.size()) + " values for " +
                    std::to_string(points.size()) + " points");
    for (size_t i = 0; i < points.size(); ++i) {
        const glm::vec3& p = points[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error("point " + std::to_string(i) + " is not finite (NaN or Inf)");
    }
    for (size_t i = 0; i < radius.size(); ++i) {
        if (!std::isfinite(radius[i])) throw Error("radius[" + std::to_string(i) + "] is not finite");
        if (radius[i] < 0.0f)
            throw Error("radius[" + std::to_string(i) + "] is negative (" +
                        std::to_string(radius[i]) + ")");
    }
    for (const auto& [name, attribute] : attributes) {
        const size_t expected =
            domain_size(*this, attribute.domain) * static_cast<size_t>(attribute.components);
        if (attribute.components < 1 || attribute.values.size() != expected)
            throw Error("attribute '" + name + "' has " + std::to_string(attribute.values.size()) +
                        " values, expected " + std::to_string(expected));
    }
}

void StrandSet::require_float_range(std::string_view what) const {
    glm::vec3 lower(std::numeric_limits<float>::max()), upper(std::numeric_limits<float>::lowest());
    float largest = 0.0f;
    for (const glm::vec3& p : points) {
        lower = glm::min(lower, p);
        upper = glm::max(upper, p);
    }
    for (float r : radius) largest = std::max(largest, r);
    if (points.empty()) return;
    largest = std::max({largest, std::abs(lower.x), std::abs(lower.y), std::abs(lower.z), std::abs(upper.x),
                        std::abs(upper.y), std::abs(upper.z)});
    char text[160];
    if (largest > kMaxCoordinate) {
        std::snprintf(text, sizeof text, ": coordinates or radii reach %.3g; hairlod computes in float32 and "
                      "supports magnitudes up to %.0e (scale the hair down)", static_cast<double>(largest),
                      static_cast<double>(kMaxCoordinate));
        throw Error(std::string(what) + text);
    }
    const double extent = glm::distance(glm::dvec3(lower), glm::dvec3(upper));
    if (extent > 0.0 && extent < kMinExtent) {
        std::snprintf(text, sizeof text, ": the hair is %.3g across; hairlod computes in float32 and supports "
                      "hair at least %.0e across (scale the hair up)", extent, static_cast<double>(kMinExtent));
        throw Error(std::string(what) + text);
    }
}

StrandSet strands_from_counts(std::vector<glm::vec3> points, std::span<const int64_t> counts,
                              std::vector<float> radius) {
    StrandSet strands;
    strands.offsets.reserve(counts.size() + 1);
    int64_t total = 0;
    for (int64_t count : counts) {
        total += count;
        strands.offsets.push_back(total);
    }
    strands.points = std::move(points);
    strands.radius = radius.empty() ? std::vector<float>(strands.points.size(), 0.0f)
                                    : std::move(radius);
    strands.validate();
    return strands;
}

}  // namespace hairlod
