#pragma once
// A pinhole camera (look-at, vertical field of view, resolution) generating primary rays.
#include <glm/vec3.hpp>

namespace hairlod::render {

struct CameraRay {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  // unit
};

class PinholeCamera {
public:
    // Throws hairlod::Error naming the bad argument (eye == target, up parallel to the view,
    // fov_y outside (0, pi), non-positive resolution).
    PinholeCamera(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float fov_y, int width,
                  int height);
    // The ray through image position (x, y) in pixels, y down from the top row.
    CameraRay ray(double x, double y) const;
    int width() const { return width_; }
    int height() const { return height_; }
    const glm::vec3& eye() const { return eye_; }

private:
    glm::vec3 eye_, forward_, right_, up_;
    float tan_half_ = 1.0f;
    int width_ = 1, height_ = 1;
};

}  // namespace hairlod::render
