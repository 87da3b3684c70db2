#include "hairlod/render/camera.h"

#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod::render {

PinholeCamera::PinholeCamera(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float fov_y,
                             int width, int height)
    : eye_(eye), width_(width), height_(height) {
    if (!(fov_y > 0.0f && fov_y < std::numbers::pi_v<float>))
        throw Error("camera: fov_y must be in (0, pi) radians, got " + std::to_string(fov_y));
    if (width < 1 || height < 1)
        throw Error("camera: resolution must be positive, got " + std::to_string(width) + "x" + std::to_string(height));
    const glm::vec3 view = target - eye;
    if (!(glm::length(view) > 0.0f)) throw Error("camera: eye and target coincide");
    forward_ = glm::normalize(view);
    const glm::vec3 side = glm::cross(forward_, up);
    if (!(glm::length(side) > 1e-6f)) throw Error("camera: the view direction is parallel to 'up'");
    right_ = glm::normalize(side);
    up_ = glm::cross(right_, forward_);
    tan_half_ = std::tan(0.5f * fov_y);
}

CameraRay PinholeCamera::ray(double x, double y) const {
    const double aspect = static_cast<double>(width_) / height_;
    const double sx = (2.0 * x / width_ - 1.0) * tan_half_ * aspect;
    const double sy = (1.0 - 2.0 * y / height_) * tan_half_;
    const glm::vec3 d = forward_ + static_cast<float>(sx) * right_ + static_cast<float>(sy) * up_;
    return {eye_, glm::normalize(d)};
}

}  // namespace hairlod::render
