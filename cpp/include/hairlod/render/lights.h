#pragma once
// Lights of the reference renderer: directional (delta), point (delta) and an environment that is
// constant or an equirectangular image (Blender's mapping, z up).
#include <vector>

#include <glm/vec3.hpp>

namespace hairlod::render {

struct DirectionalLight {
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  // the way light travels (unit)
    glm::vec3 irradiance{1.0f};              // on a surface facing the light
};

struct PointLight {
    glm::vec3 position{0.0f};
    glm::vec3 intensity{1.0f};  // radiant intensity (W/sr)
};

class Environment {
public:
    Environment() = default;
    explicit Environment(const glm::vec3& constant) : constant_(constant) {}
    // Equirectangular radiance, `height` rows of `width` RGB texels, top row = up (+z).
    Environment(int width, int height, std::vector<glm::vec3> texels);
    // Radiance arriving from direction `towards` (unit, pointing away from the scene).
    glm::vec3 radiance(const glm::vec3& towards) const;
    bool black() const;

private:
    glm::vec3 constant_{0.0f};
    int width_ = 0, height_ = 0;
    std::vector<glm::vec3> texels_;
};

struct Lights {
    std::vector<DirectionalLight> directional;
    std::vector<PointLight> points;
    Environment environment;
    // Throws hairlod::Error naming the first light with a zero direction or non-finite / negative power.
    void validate() const;
};

}  // namespace hairlod::render
