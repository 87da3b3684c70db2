#include "hairlod/render/lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod::render {

namespace {

bool finite_non_negative(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f;
}

}  // namespace

Environment::Environment(int width, int height, std::vector<glm::vec3> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {
    if (width < 1 || height < 1 || texels_.size() != static_cast<size_t>(width) * height)
        throw Error("environment: need height x width RGB texels, got " + std::to_string(texels_.size()) + " for " +
                    std::to_string(width) + "x" + std::to_string(height));
    for (const glm::vec3& t : texels_)
        if (!finite_non_negative(t)) throw Error("environment: texels must be finite and >= 0");
}

glm::vec3 Environment::radiance(const glm::vec3& w) const {
    if (texels_.empty()) return constant_;
    // Blender's equirectangular mapping: u = -atan2(y, x) / 2 pi + 1/2, v = atan2(z, hypot(x, y)) / pi + 1/2.
    const double u = -std::atan2(w.y, w.x) / (2.0 * std::numbers::pi) + 0.5;
    const double v = std::atan2(w.z, std::hypot(w.x, w.y)) / std::numbers::pi + 0.5;
    const int column = std::clamp(static_cast<int>(u * width_), 0, width_ - 1);
    const int row = std::clamp(static_cast<int>((1.0 - v) * height_), 0, height_ - 1);
    return texels_[static_cast<size_t>(row) * width_ + column];
}

bool Environment::black() const {
    if (texels_.empty()) return constant_ == glm::vec3(0.0f);
    return std::all_of(texels_.begin(), texels_.end(), [](const glm::vec3& t) { return t == glm::vec3(0.0f); });
}

void Lights::validate() const {
    for (size_t i = 0; i < directional.size(); ++i) {
        if (!(glm::length(directional[i].direction) > 0.0f))
            throw Error("directional light " + std::to_string(i) + ": direction is zero");
        if (!finite_non_negative(directional[i].irradiance))
            throw Error("directional light " + std::to_string(i) + ": irradiance must be finite and >= 0");
    }
    for (size_t i = 0; i < points.size(); ++i)
        if (!finite_non_negative(points[i].intensity) || !std::isfinite(points[i].position.x + points[i].position.y + points[i].position.z))
            throw Error("point light " + std::to_string(i) + ": position and intensity must be finite, intensity >= 0");
}

}  // namespace hairlod::render
