#include "hairlod/core/strand_set.h"

#include <cmath>
#include <string>

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
