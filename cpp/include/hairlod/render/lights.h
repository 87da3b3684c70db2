#pragma once
// Lights of the reference renderer: directional (delta), point (delta) and an environment that is
// constant or an equirectangular image (Blender's mapping, z up), sampled in proportion to its
// luminance per solid angle.
#include <vector>

#include <glm/vec3.hpp>

namespace hairlod::render {

struct DirectionalLight {
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  // the way light travels (unit)
    glm::vec3 irradiance{1.0f};              // on a surface facing the light
};

// A direction towards the environment and its density per unit solid angle.
struct EnvironmentSample {
    glm::vec3 towards{0.0f, 0.0f, 1.0f};
    double pdf = 0.0;
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
    // A direction drawn from uniforms u1, u2 in [0, 1): uniform over the sphere for a constant
    // environment; for an image, a texel in proportion to its luminance times its solid angle, then a
    // point uniform in the texel's (u, v) rectangle (PBRT's piecewise-constant 2D distribution, Pharr
    // et al. 2016 Sec. 13.6.7 and 14.2.4). An image's texels of luminance 0 are never drawn.
    EnvironmentSample sample(double u1, double u2) const;
    // The density of sample() at `towards` (unit), per unit solid angle.
    double pdf(const glm::vec3& towards) const;

private:
    void build_distribution();

    glm::vec3 constant_{0.0f};
    int width_ = 0, height_ = 0;
    std::vector<glm::vec3> texels_;
    // Cumulative luminance x solid angle: over the rows (height_ + 1, from 0 to 1) and, per row, over its
    // columns (height_ x (width_ + 1), each from 0 to 1); the rows' and texels' probabilities.
    std::vector<double> row_cdf_, column_cdf_, row_probability_, texel_probability_;
};

struct Lights {
    std::vector<DirectionalLight> directional;
    std::vector<PointLight> points;
    Environment environment;
    // Throws hairlod::Error naming the first light with a zero direction or non-finite / negative power.
    void validate() const;
};

}  // namespace hairlod::render
