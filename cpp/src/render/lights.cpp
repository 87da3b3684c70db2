#include "hairlod/render/lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod::render {

namespace {

constexpr double kPi = std::numbers::pi;

bool finite_non_negative(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f;
}

// Rec. 709 luminance: how much a texel is worth drawing (any positive weight would be unbiased).
double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// The index k with cdf[k] <= u < cdf[k + 1] among the cdf's size - 1 intervals, skipping empty ones.
size_t find_interval(const double* cdf, size_t intervals, double u) {
    const double* upper = std::upper_bound(cdf + 1, cdf + intervals, u);
    size_t k = static_cast<size_t>(upper - cdf) - 1;
    while (k + 1 < intervals && !(cdf[k + 1] > cdf[k])) ++k;  // u on a boundary below an empty interval
    return k;
}

}  // namespace

Environment::Environment(int width, int height, std::vector<glm::vec3> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {
    if (width < 1 || height < 1 || texels_.size() != static_cast<size_t>(width) * height)
        throw Error("environment: need height x width RGB texels, got " + std::to_string(texels_.size()) + " for " +
                    std::to_string(width) + "x" + std::to_string(height));
    for (const glm::vec3& t : texels_)
        if (!finite_non_negative(t)) throw Error("environment: texels must be finite and >= 0");
    build_distribution();
}

void Environment::build_distribution() {
    // Texel (row r, column c) spans v in [1 - (r + 1) / H, 1 - r / H] (top row up), elevation (v - 1/2) pi,
    // and solid angle 2 pi^2 cos(elevation) du dv: weight = luminance x cos(elevation at its centre).
    row_cdf_.assign(static_cast<size_t>(height_) + 1, 0.0);
    column_cdf_.assign(static_cast<size_t>(height_) * (width_ + 1), 0.0);
    row_probability_.assign(static_cast<size_t>(height_), 0.0);
    texel_probability_.assign(texels_.size(), 0.0);
    for (int r = 0; r < height_; ++r) {
        const double elevation = (0.5 - (r + 0.5) / height_) * kPi;
        double* cdf = &column_cdf_[static_cast<size_t>(r) * (width_ + 1)];
        for (int c = 0; c < width_; ++c)
            cdf[c + 1] = cdf[c] + luminance(texels_[static_cast<size_t>(r) * width_ + c]) * std::cos(elevation);
        row_cdf_[r + 1] = row_cdf_[r] + cdf[width_];
    }
    const double total = row_cdf_[height_];
    if (!(total > 0.0)) return;  // black: nothing to draw (the integrator does not sample it)
    for (int r = 0; r < height_; ++r) {
        double* cdf = &column_cdf_[static_cast<size_t>(r) * (width_ + 1)];
        const double row_total = cdf[width_];
        row_probability_[r] = row_total / total;
        for (int c = 0; c < width_; ++c)
            texel_probability_[static_cast<size_t>(r) * width_ + c] = (cdf[c + 1] - cdf[c]) / total;
        if (row_total > 0.0)
            for (int c = 1; c <= width_; ++c) cdf[c] /= row_total;
    }
    for (int r = 1; r <= height_; ++r) row_cdf_[r] /= total;
}

EnvironmentSample Environment::sample(double u1, double u2) const {
    EnvironmentSample out;
    if (texels_.empty() || !(row_cdf_.back() > 0.0)) {
        // Uniform over the sphere.
        const double z = 1.0 - 2.0 * u1, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
        out.towards = glm::vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
        out.pdf = texels_.empty() ? 1.0 / (4.0 * kPi) : 0.0;
        return out;
    }
    const size_t row = find_interval(row_cdf_.data(), static_cast<size_t>(height_), u1);
    const double* cdf = &column_cdf_[row * (width_ + 1)];
    const size_t column = find_interval(cdf, static_cast<size_t>(width_), u2);
    // Uniform within the texel, by the uniforms' remainders in their intervals.
    const double in_row = std::clamp((u1 - row_cdf_[row]) / std::max(row_cdf_[row + 1] - row_cdf_[row], 1e-300), 0.0, 1.0);
    const double in_column = std::clamp((u2 - cdf[column]) / std::max(cdf[column + 1] - cdf[column], 1e-300), 0.0, 1.0);
    const double u = (double(column) + in_column) / width_;
    const double v = 1.0 - (double(row) + in_row) / height_;
    const double elevation = (v - 0.5) * kPi, azimuth = -2.0 * kPi * (u - 0.5);
    const double cos_elevation = std::cos(elevation);
    out.towards = glm::vec3(float(cos_elevation * std::cos(azimuth)), float(cos_elevation * std::sin(azimuth)),
                            float(std::sin(elevation)));
    // Density in (u, v): the texel's probability over its area 1 / (W H); per solid angle / (2 pi^2 cos).
    const double texel = texel_probability_[row * width_ + column];
    out.pdf = cos_elevation > 0.0 ? texel * double(width_) * height_ / (2.0 * kPi * kPi * cos_elevation) : 0.0;
    return out;
}

double Environment::pdf(const glm::vec3& w) const {
    if (texels_.empty()) return 1.0 / (4.0 * kPi);
    if (!(row_cdf_.back() > 0.0)) return 0.0;
    const double u = -std::atan2(w.y, w.x) / (2.0 * kPi) + 0.5;
    const double v = std::atan2(w.z, std::hypot(w.x, w.y)) / kPi + 0.5;
    const int column = std::clamp(static_cast<int>(u * width_), 0, width_ - 1);
    const int row = std::clamp(static_cast<int>((1.0 - v) * height_), 0, height_ - 1);
    const double cos_elevation = std::cos((v - 0.5) * kPi);
    const double texel = texel_probability_[static_cast<size_t>(row) * width_ + column];
    return cos_elevation > 0.0 ? texel * double(width_) * height_ / (2.0 * kPi * kPi * cos_elevation) : 0.0;
}

glm::vec3 Environment::radiance(const glm::vec3& w) const {
    if (texels_.empty()) return constant_;
    // Blender's equirectangular mapping: u = -atan2(y, x) / 2 pi + 1/2, v = atan2(z, hypot(x, y)) / pi + 1/2.
    const double u = -std::atan2(w.y, w.x) / (2.0 * kPi) + 0.5;
    const double v = std::atan2(w.z, std::hypot(w.x, w.y)) / kPi + 0.5;
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
