// hairlod._core render bindings: one call that builds the Embree scene, renders and returns the
// image with its statistics. Parsing of cameras, lights and views lives in hairlod/render.py.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "numpy_arrays.h"
#include "hairlod/core/error.h"
#include "hairlod/render/integrator.h"

namespace py = pybind11;

namespace hairlod::python {

namespace {

using namespace hairlod::render;

glm::vec3 vec3(const std::array<float, 3>& v) { return {v[0], v[1], v[2]}; }

template <typename T>
std::vector<T> rows(const FloatArray& array, int columns, const char* name) {
    const std::span<const T> view = rows_of<T>(array, columns, name);
    return {view.begin(), view.end()};
}

ThickHairs thick_from(const py::dict& d) {
    ThickHairs hairs;
    hairs.centres = rows<glm::vec3>(d["centres"].cast<FloatArray>(), 3, "thick centres");
    const Int64Array offsets = d["offsets"].cast<Int64Array>();
    hairs.offsets.assign(offsets.data(), offsets.data() + offsets.size());
    hairs.major_axis = rows<glm::vec3>(d["major_axis"].cast<FloatArray>(), 3, "thick major_axis");
    hairs.radii = rows<glm::vec2>(d["radii"].cast<FloatArray>(), 2, "thick radii");
    const FloatArray density = d["density"].cast<FloatArray>();
    hairs.density.assign(density.data(), density.data() + density.size());
    const FloatArray n_total = d["n_total"].cast<FloatArray>();
    hairs.n_total.assign(n_total.data(), n_total.data() + n_total.size());
    return hairs;
}

Lights lights_from(const py::dict& d) {
    Lights lights;
    if (d.contains("directional"))
        for (const auto& [direction, irradiance] : d["directional"].cast<std::vector<std::pair<std::array<float, 3>, std::array<float, 3>>>>())
            lights.directional.push_back({vec3(direction), vec3(irradiance)});
    if (d.contains("points"))
        for (const auto& [position, intensity] : d["points"].cast<std::vector<std::pair<std::array<float, 3>, std::array<float, 3>>>>())
            lights.points.push_back({vec3(position), vec3(intensity)});
    if (d.contains("environment") && !d["environment"].is_none()) {
        const FloatArray env = d["environment"].cast<FloatArray>();
        if (env.ndim() == 1 && env.shape(0) == 3) {
            lights.environment = Environment(glm::vec3(env.data()[0], env.data()[1], env.data()[2]));
        } else if (env.ndim() == 3 && env.shape(2) == 3) {
            const auto* data = reinterpret_cast<const glm::vec3*>(env.data());
            lights.environment = Environment(static_cast<int>(env.shape(1)), static_cast<int>(env.shape(0)),
                                             std::vector<glm::vec3>(data, data + env.shape(0) * env.shape(1)));
        } else {
            throw Error("environment must be an RGB triple or an equirectangular image [H, W, 3]");
        }
    }
    return lights;
}

}  // namespace

void bind_render(py::module_& m) {
    m.attr("DEFAULT_MAX_BOUNCES") = RenderOptions{}.max_bounces;
    m.def(
        "render",
        [](const std::optional<StrandSet>& strands, const std::optional<py::dict>& thick, const py::dict& camera,
           const py::dict& lights_dict, const bcsdf::HairParams& params, const std::string& method, int spp,
           int max_bounces, uint64_t seed, bool coverage_only, const std::optional<std::function<void(double)>>& progress,
           const std::optional<std::string>& own_hair) {
            const PinholeCamera cam(vec3(camera["eye"].cast<std::array<float, 3>>()),
                                    vec3(camera["target"].cast<std::array<float, 3>>()),
                                    vec3(camera["up"].cast<std::array<float, 3>>()), camera["fov_y"].cast<float>(),
                                    camera["width"].cast<int>(), camera["height"].cast<int>());
            const Lights lights = lights_from(lights_dict);
            std::optional<ThickHairs> hairs;
            if (thick) hairs = thick_from(*thick);
            RenderOptions options;
            options.method = parse_method(method);
            options.spp = spp;
            options.max_bounces = max_bounces;
            if (own_hair) options.own_hair = parse_own_hair(*own_hair);
            options.seed = seed;
            options.coverage_only = coverage_only;
            RenderStats stats;
            Image image;
            size_t strand_segments = 0, thick_segments = 0;
            {
                py::gil_scoped_release release;
                auto device = std::make_shared<Device>();
                HairScene scene(device);
                if (strands) scene.add_strands(*strands);
                if (hairs) scene.add_thick_hairs(*hairs);
                scene.commit();
                strand_segments = scene.segment_count(CurveKind::Strand);
                thick_segments = scene.segment_count(CurveKind::Thick);
                Progress report;
                if (progress)
                    report = [&](double fraction) {
                        py::gil_scoped_acquire acquire;
                        (*progress)(fraction);
                    };
                image = hairlod::render::render(scene, cam, lights, params, options, &stats, report);
            }
            py::array_t<float> pixels({image.height, image.width, 3});
            std::copy_n(reinterpret_cast<const float*>(image.pixels.data()), 3 * image.pixels.size(), pixels.mutable_data());
            py::dict out;
            out["image"] = pixels;
            out["seconds"] = stats.seconds;
            out["setup_seconds"] = stats.setup_seconds;
            out["rays"] = stats.rays;
            out["rays_per_second"] = stats.rays_per_second();
            out["strand_segments"] = strand_segments;
            out["thick_segments"] = thick_segments;
            return out;
        },
        py::arg("strands"), py::arg("thick"), py::arg("camera"), py::arg("lights"), py::arg("params"),
        py::arg("method") = "pt", py::arg("spp") = 16, py::arg("max_bounces") = RenderOptions{}.max_bounces, py::arg("seed") = 0,
        py::arg("coverage_only") = false, py::arg("progress") = py::none(), py::arg("own_hair") = py::none(),
        R"doc(Renders strands and/or thick hairs (dict of centres [N,3], offsets, major_axis [N,3], radii [N,2],
density [N], n_total [H]) with the Embree reference renderer. camera: eye, target, up, fov_y (radians),
width, height. coverage_only: black hair (with a white environment the image is 1 - alpha). own_hair:
"attenuate" (default) or "scatter" (lod-single: paths scatter at their thick hair's own strands). lights: directional [(direction, irradiance)], points [(position, intensity)],
environment (RGB or equirect [H,W,3]). Returns image [H,W,3] float32 (linear), seconds, setup_seconds,
rays, rays_per_second, strand_segments, thick_segments.)doc");
}

}  // namespace hairlod::python
