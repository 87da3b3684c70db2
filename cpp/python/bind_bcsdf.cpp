// hairlod._core bcsdf bindings: HairParams, the Principled Hair conversion, batched evaluation,
// white furnace and dual scattering. Thin: parsing of model inputs lives in hairlod/bcsdf.py.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "numpy_arrays.h"
#include "hairlod/bcsdf/bake.h"
#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/chiang_stand_in.h"
#include "hairlod/bcsdf/dual_scattering.h"
#include "hairlod/bcsdf/exr_writer.h"
#include "hairlod/bcsdf/fiber_rtd.h"
#include "hairlod/bcsdf/furnace.h"
#include "hairlod/bcsdf/huang.h"
#include "hairlod/bcsdf/model_factory.h"
#include "hairlod/bcsdf/principled_hair.h"
#include "hairlod/bcsdf/srbf.h"
#include "hairlod/bcsdf/srbf_multiple_scattering.h"
#include "hairlod/core/error.h"

namespace py = pybind11;

namespace hairlod::python {

namespace {

using namespace hairlod::bcsdf;

glm::dvec3 to_dvec3(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }
std::array<double, 3> to_array(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

// SRBF lights from their directions [N, 3], bandwidths [N] and RGB coefficients [N, 3].
std::vector<SrbfLight> srbf_lights(const DoubleArray& directions, const DoubleArray& lambdas, const DoubleArray& coefficients) {
    if (directions.ndim() != 2 || directions.shape(1) != 3) throw Error("light directions must have shape [N, 3]");
    const py::ssize_t count = directions.shape(0);
    if (lambdas.ndim() != 1 || lambdas.shape(0) != count) throw Error("lambdas must have shape [N]");
    if (coefficients.ndim() != 2 || coefficients.shape(0) != count || coefficients.shape(1) != 3)
        throw Error("coefficients must have shape [N, 3]");
    std::vector<SrbfLight> lights(static_cast<size_t>(count));
    for (py::ssize_t j = 0; j < count; ++j)
        lights[j] = {{directions.at(j, 0), directions.at(j, 1), directions.at(j, 2)}, lambdas.at(j),
                     {coefficients.at(j, 0), coefficients.at(j, 1), coefficients.at(j, 2)}};
    return lights;
}

PrincipledParametrization parse_parametrization(const std::string& name) {
    if (name == "ABSORPTION") return PrincipledParametrization::AbsorptionCoefficient;
    if (name == "MELANIN") return PrincipledParametrization::MelaninConcentration;
    if (name == "COLOR") return PrincipledParametrization::DirectColoring;
    throw Error("parametrization must be 'ABSORPTION', 'MELANIN' or 'COLOR', got '" + name + "'");
}

PrincipledModel parse_principled_model(const std::string& name) {
    if (name == "CHIANG") return PrincipledModel::Chiang;
    if (name == "HUANG") return PrincipledModel::Huang;
    throw Error("model must be 'CHIANG' or 'HUANG', got '" + name + "'");
}

FibreModel parse_fibre(const std::string& name) {
    if (name == "chiang") return FibreModel::Chiang;
    if (name == "huang") return FibreModel::Huang;
    throw Error("fibre must be 'chiang' or 'huang', got '" + name + "'");
}

RealtimeTT parse_realtime_tt(const std::string& name) {
    if (name == "tafuri") return RealtimeTT::Tafuri;
    if (name == "karis") return RealtimeTT::Karis;
    throw Error("tt must be 'tafuri' or 'karis', got '" + name + "'");
}

std::array<double, 3> white_furnace_of(const std::string& model, const HairParams& params, const std::array<double, 3>& wo,
                                       std::optional<double> h, double tolerance, const std::string& tt) {
    const QuadratureTolerance tol{tolerance, tolerance, 30};
    ModelOptions options;
    options.realtime_tt = parse_realtime_tt(tt);
    py::gil_scoped_release release;
    const BcsdfModel kind = parse_bcsdf_model(model);
    if (h) {
        if (kind != BcsdfModel::Chiang) throw Error("h (near field) applies to the chiang model only");
        return to_array(white_furnace_near_field(ChiangBcsdf(params), to_dvec3(wo), *h, tol));
    }
    return to_array(white_furnace(*make_bcsdf(kind, params, options), to_dvec3(wo), tol));
}

}  // namespace

void bind_bcsdf(py::module_& m) {
    py::class_<HairParams>(m, "HairParams", R"doc(
Physical parameters of one hair fibre (fields as in C++ hairlod::bcsdf::HairParams).

eta             index of refraction (> 1)
sigma_a         absorption per unit fibre radius, RGB (>= 0)
beta_m, beta_n  longitudinal / azimuthal roughness in (0, 1] (pbrt convention)
alpha           cuticle tilt in radians (pbrt/Cycles sign)
coat            [0, 1]: R-lobe roughness is (1 - coat) beta_m (Cycles)
eccentricity    Marschner's a in (1/sqrt(2), sqrt(2)); 1 is circular
weight_r, weight_tt, weight_trt   lobe multipliers (TRT includes every higher order)
fibre           'chiang' or 'huang': the fibre the path tracer shades strands with
microfacet_roughness, aspect_ratio, huang_sigma_a   the Huang fibre's GGX roughness [0.001, 1], minor/major
                axis [0.1, 1] and absorption (sigma_a, beta_m, beta_n are then its Chiang stand-in's))doc")
        .def(py::init<>())
        .def_readwrite("eta", &HairParams::eta)
        .def_property(
            "sigma_a", [](const HairParams& p) { return to_array(p.sigma_a); },
            [](HairParams& p, const std::array<double, 3>& v) { p.sigma_a = to_dvec3(v); })
        .def_readwrite("beta_m", &HairParams::beta_m)
        .def_readwrite("beta_n", &HairParams::beta_n)
        .def_readwrite("alpha", &HairParams::alpha)
        .def_readwrite("coat", &HairParams::coat)
        .def_readwrite("eccentricity", &HairParams::eccentricity)
        .def_readwrite("weight_r", &HairParams::weight_r)
        .def_readwrite("weight_tt", &HairParams::weight_tt)
        .def_readwrite("weight_trt", &HairParams::weight_trt)
        .def_property(
            "fibre", [](const HairParams& p) { return std::string(p.fibre == FibreModel::Huang ? "huang" : "chiang"); },
            [](HairParams& p, const std::string& name) { p.fibre = parse_fibre(name); })
        .def_readwrite("microfacet_roughness", &HairParams::microfacet_roughness)
        .def_readwrite("aspect_ratio", &HairParams::aspect_ratio)
        .def_property(
            "huang_sigma_a", [](const HairParams& p) { return to_array(p.huang_sigma_a); },
            [](HairParams& p, const std::array<double, 3>& v) { p.huang_sigma_a = to_dvec3(v); })
        .def("validate", &HairParams::validate, "Raises ValueError naming the first invalid parameter.");

    m.def("sigma_a_from_color",
          [](const std::array<double, 3>& color, double beta_n) { return to_array(sigma_a_from_color(to_dvec3(color), beta_n)); },
          py::arg("color"), py::arg("beta_n"), "Chiang et al. 2016, Eq. 9: absorption from a reflectance colour.");
    m.def("sigma_a_from_melanin",
          [](double eumelanin, double pheomelanin) { return to_array(sigma_a_from_melanin(eumelanin, pheomelanin)); },
          py::arg("eumelanin"), py::arg("pheomelanin") = 0.0, "Absorption of melanin concentrations (Cycles).");
    m.def(
        "params_from_principled_hair",
        [](const std::string& parametrization, const std::array<double, 3>& color, double melanin,
           double melanin_redness, const std::array<double, 3>& tint, const std::array<double, 3>& absorption_coefficient,
           double roughness, double radial_roughness, double coat, double ior, double offset, const std::string& model,
           double aspect_ratio, double reflection, double transmission, double secondary_reflection) {
            PrincipledHairInputs in;
            in.model = parse_principled_model(model);
            in.aspect_ratio = aspect_ratio;
            in.reflection = reflection;
            in.transmission = transmission;
            in.secondary_reflection = secondary_reflection;
            in.parametrization = parse_parametrization(parametrization);
            in.color = to_dvec3(color);
            in.melanin = melanin;
            in.melanin_redness = melanin_redness;
            in.tint = to_dvec3(tint);
            in.absorption_coefficient = to_dvec3(absorption_coefficient);
            in.roughness = roughness;
            in.radial_roughness = radial_roughness;
            in.coat = coat;
            in.ior = ior;
            in.offset = offset;
            py::gil_scoped_release release;
            return params_from_principled_hair(in);
        },
        py::arg("parametrization"), py::arg("color"), py::arg("melanin"), py::arg("melanin_redness"), py::arg("tint"),
        py::arg("absorption_coefficient"), py::arg("roughness"), py::arg("radial_roughness"), py::arg("coat"),
        py::arg("ior"), py::arg("offset"), py::arg("model") = "CHIANG", py::arg("aspect_ratio") = 0.85,
        py::arg("reflection") = 1.0, py::arg("transmission") = 1.0, py::arg("secondary_reflection") = 1.0);

    m.def(
        "chiang_stand_in",
        [](const HairParams& params) {
            ChiangStandIn stand_in;
            {
                py::gil_scoped_release release;
                stand_in = chiang_stand_in(params);
            }
            const auto albedo = [](const FibreAlbedo& a) {
                return py::dict(py::arg("surface") = to_array(a.surface), py::arg("interior") = to_array(a.interior));
            };
            return py::make_tuple(stand_in.params, albedo(stand_in.huang), albedo(stand_in.stand_in));
        },
        py::arg("params"),
        "(params with sigma_a, beta_m, beta_n of the Chiang fibre standing in for the Huang fibre, the Huang "
        "fibre's albedo, the stand-in's albedo); each albedo a dict of RGB 'surface' (R) and 'interior' parts, "
        "averaged over views.");

    m.def(
        "huang_sample",
        [](const HairParams& params, const DoubleArray& wo, const DoubleArray& u) {
            if (wo.ndim() != 2 || wo.shape(1) != 3) throw Error("wo must have shape [N, 3]");
            if (u.ndim() != 2 || u.shape(0) != wo.shape(0) || u.shape(1) != 11) throw Error("u must have shape [N, 11]");
            const py::ssize_t n = wo.shape(0);
            py::array_t<double> wi({n, py::ssize_t(3)}), weight({n, py::ssize_t(3)}), discarded({n, py::ssize_t(3)});
            const HuangBcsdf model(params);
            double* wi_out = wi.mutable_data();
            double* weight_out = weight.mutable_data();
            double* discarded_out = discarded.mutable_data();
            const double* w = wo.data();
            const double* uu = u.data();
            {
                py::gil_scoped_release release;
                for (py::ssize_t k = 0; k < n; ++k) {
                    std::array<double, 11> draw;
                    std::copy(uu + 11 * k, uu + 11 * (k + 1), draw.begin());
                    const FibreSample sample = model.sample({w[3 * k], w[3 * k + 1], w[3 * k + 2]}, draw);
                    for (int c = 0; c < 3; ++c) {
                        wi_out[3 * k + c] = sample.wi[c];
                        weight_out[3 * k + c] = sample.weight[c];
                        discarded_out[3 * k + c] = sample.discarded[c];
                    }
                }
            }
            return py::make_tuple(wi, weight, discarded);
        },
        py::arg("params"), py::arg("wo"), py::arg("u"),
        "Huang fibre sampling: (wi [N, 3], weight S cos(theta_i) / pdf [N, 3], discarded [N, 3]: the throughput the "
        "model's visibility rules drop) for wo [N, 3] and uniforms u [N, 11].");

    m.def(
        "bcsdf_evaluate",
        [](const std::string& model, const HairParams& params, const FloatArray& wi, const FloatArray& wo,
           const std::optional<FloatArray>& h, const std::string& tt, double caustic_width, double caustic_fade_range,
           double caustic_max_window, double hair_count, double density, int residual_samples,
           const std::string& aggregated_fibre) {
            const std::span<const glm::vec3> in = rows_of<glm::vec3>(wi, 3, "wi");
            const std::span<const glm::vec3> out_dirs = rows_of<glm::vec3>(wo, 3, "wo");
            if (in.size() != out_dirs.size()) throw Error("wi and wo must have the same number of directions");
            std::optional<std::span<const float>> offsets;
            if (h) {
                if (h->ndim() != 1) throw Error("h must have shape [N]");
                offsets = std::span<const float>(h->data(), static_cast<size_t>(h->size()));
            }
            py::array_t<float> result({static_cast<py::ssize_t>(in.size()), py::ssize_t(3)});
            const std::span<glm::vec3> values(reinterpret_cast<glm::vec3*>(result.mutable_data()), in.size());
            ModelOptions options;
            options.realtime_tt = parse_realtime_tt(tt);
            options.marschner_caustic = {caustic_width, caustic_fade_range, caustic_max_window};
            options.cluster = {hair_count, density};
            if (aggregated_fibre == "material") options.aggregated_fibre = AggregatedFibre::Material;
            else if (aggregated_fibre != "rtd")
                throw Error("aggregated_fibre must be 'rtd' or 'material', got '" + aggregated_fibre + "'");
            if (residual_samples < 1) throw Error("residual_samples must be >= 1, got " + std::to_string(residual_samples));
            options.huang_residual_samples = residual_samples;
            const BcsdfModel kind = parse_bcsdf_model(model);
            {
                py::gil_scoped_release release;
                if (offsets) {
                    if (kind != BcsdfModel::Chiang) throw Error("h (near field) applies to the chiang model only");
                    evaluate_near_field(ChiangBcsdf(params), in, out_dirs, *offsets, values);
                } else {
                    evaluate(*make_bcsdf(kind, params, options), in, out_dirs, values);
                }
            }
            return result;
        },
        py::arg("model"), py::arg("params"), py::arg("wi"), py::arg("wo"), py::arg("h") = py::none(),
        py::arg("tt") = "tafuri", py::arg("caustic_width") = MarschnerCaustic{}.width,
        py::arg("caustic_fade_range") = MarschnerCaustic{}.fade_range,
        py::arg("caustic_max_window") = MarschnerCaustic{}.max_window, py::arg("hair_count") = 1.0,
        py::arg("density") = 1.0, py::arg("residual_samples") = HuangBcsdf::kDefaultResidualSamples,
        py::arg("aggregated_fibre") = "rtd", "S(wi, wo) as float32 [N, 3]; directions in the fibre frame (tangent +x).");

    m.attr("DEFAULT_FORWARD_DENSITY") = kDefaultForwardDensity;
    m.attr("DEFAULT_BACKSCATTER_DENSITY") = kDefaultBackscatterDensity;
    m.def("cluster_density", &cluster_density, py::arg("hair_total"), py::arg("hair_radius"), py::arg("major_axis"),
          py::arg("minor_axis"), "Huang et al. 2025, Sec. 4: rho = n_total r^2 / (|r_A| |r_B|), at most 1.");
    m.def("hairs_crossed", &hairs_crossed, py::arg("density"), py::arg("ray_length"), py::arg("hair_total"),
          py::arg("major_axis"), py::arg("minor_axis"),
          "Huang et al. 2025, Sec. 4: n = rho l sqrt(n_total / (pi |r_A| |r_B|)), at least 1.");
    m.def("expected_hairs_met", &expected_hairs_met, py::arg("density"), py::arg("ray_length"), py::arg("hair_total"),
          py::arg("major_axis"), py::arg("minor_axis"),
          "The strands a ray meets on average over ray_length of in-plane path through a thick hair (Poisson "
          "mean, what the renderer's thick hairs use): 2 r n_total l / (pi |r_A| |r_B|), r from Sec. 4's rho.");
    m.def("max_hairs_crossed", [](const FloatArray& n_total, const FloatArray& radii, const FloatArray& density) {
              if (n_total.ndim() != 1) throw Error("n_total must have shape [H]");
              if (density.ndim() != 1) throw Error("density must have shape [P]");
              const std::span<const float> totals(n_total.data(), static_cast<size_t>(n_total.size()));
              const std::span<const float> densities(density.data(), static_cast<size_t>(density.size()));
              return max_hairs_crossed(totals, rows_of<glm::vec2>(radii, 2, "radii"), densities);
          }, py::arg("n_total"), py::arg("radii"), py::arg("density"),
          "Huang et al. 2025, Sec. 4 and 5.2: the most hairs a ray crosses in a level's thick hairs (at least 1).");

    m.def("bcsdf_white_furnace", &white_furnace_of, py::arg("model"), py::arg("params"), py::arg("wo"),
          py::arg("h") = py::none(), py::arg("tolerance") = 1e-6, py::arg("tt") = "tafuri",
          "Integral of S(wi, wo) cos(theta_i) dw_i by adaptive quadrature (RGB); tt picks the realtime TT variant.");

    m.def(
        "bcsdf_srbf_single_scattering",
        [](const HairParams& params, const DoubleArray& directions, const DoubleArray& lambdas,
           const DoubleArray& coefficients, const DoubleArray& wo, double caustic_width, double caustic_fade_range,
           double caustic_max_window, int m) {
            const std::vector<SrbfLight> lights = srbf_lights(directions, lambdas, coefficients);
            if (wo.ndim() != 2 || wo.shape(1) != 3) throw Error("wo must have shape [M, 3]");
            const std::span<const glm::dvec3> views(reinterpret_cast<const glm::dvec3*>(wo.data()),
                                                    static_cast<size_t>(wo.shape(0)));
            std::vector<glm::dvec3> radiance;
            {
                py::gil_scoped_release release;
                const CircularGaussianMarschner model(
                    MarschnerBcsdf(params, {caustic_width, caustic_fade_range, caustic_max_window}),
                    default_circular_gaussian_tables(), m);
                radiance = model.single_scattering(lights, views);
            }
            return to_numpy<double>(radiance, {wo.shape(0), py::ssize_t(3)});
        },
        py::arg("params"), py::arg("directions"), py::arg("lambdas"), py::arg("coefficients"), py::arg("wo"),
        py::arg("caustic_width") = MarschnerCaustic{}.width, py::arg("caustic_fade_range") = MarschnerCaustic{}.fade_range,
        py::arg("caustic_max_window") = MarschnerCaustic{}.max_window, py::arg("m") = 4,
        "Xu et al. 2011, Eq. 2 and 11: sum over SRBF lights of L_j integral G_j S cos(theta_i) dw_i (Marschner, "
        "circular Gaussian representation) per view direction, [M, 3].");

    m.def(
        "bcsdf_srbf_multiple_scattering",
        [](const HairParams& params, const DoubleArray& directions, const DoubleArray& lambdas,
           const DoubleArray& coefficients, const DoubleArray& wo, const DoubleArray& forward_attenuation,
           const DoubleArray& forward_variance, double forward_density, double backscatter_density, int table_samples,
           double caustic_width, double caustic_fade_range, double caustic_max_window, int m, bool reference,
           int theta_samples, int phi_samples) {
            const std::vector<SrbfLight> lights = srbf_lights(directions, lambdas, coefficients);
            const py::ssize_t count = directions.shape(0);
            if (forward_attenuation.ndim() != 2 || forward_attenuation.shape(0) != count || forward_attenuation.shape(1) != 3)
                throw Error("forward_attenuation must have shape [N, 3]");
            if (forward_variance.ndim() != 1 || forward_variance.shape(0) != count)
                throw Error("forward_variance must have shape [N]");
            if (wo.ndim() != 2 || wo.shape(1) != 3) throw Error("wo must have shape [M, 3]");
            std::vector<ForwardScattering> forward(static_cast<size_t>(count));
            for (py::ssize_t j = 0; j < count; ++j)
                forward[j] = {{forward_attenuation.at(j, 0), forward_attenuation.at(j, 1), forward_attenuation.at(j, 2)},
                              forward_variance.at(j)};
            const py::ssize_t views = wo.shape(0);
            const std::span<const glm::dvec3> view(reinterpret_cast<const glm::dvec3*>(wo.data()), static_cast<size_t>(views));
            std::vector<MultipleScatteringRadiance> radiance(static_cast<size_t>(views));
            {
                py::gil_scoped_release release;
                const MarschnerBcsdf marschner(params, {caustic_width, caustic_fade_range, caustic_max_window});
                BackscatterTable backscatter = backscatter_table(marschner, table_samples, backscatter_density);
                if (reference) {
                    radiance = srbf_multiple_scattering_reference(marschner, backscatter, lights, forward, view,
                                                                  forward_density, theta_samples, phi_samples);
                } else {
                    const SrbfMultipleScattering model(
                        CircularGaussianMarschner(marschner, default_circular_gaussian_tables(), m), std::move(backscatter),
                        forward_density);
                    radiance = model.eval(lights, forward, view);
                }
            }
            py::array_t<double> global({views, py::ssize_t(3)}), local({views, py::ssize_t(3)});
            for (py::ssize_t k = 0; k < views; ++k)
                for (int c = 0; c < 3; ++c) {
                    global.mutable_at(k, c) = radiance[k].global[c];
                    local.mutable_at(k, c) = radiance[k].local[c];
                }
            return py::make_tuple(global, local);
        },
        py::arg("params"), py::arg("directions"), py::arg("lambdas"), py::arg("coefficients"), py::arg("wo"),
        py::arg("forward_attenuation"), py::arg("forward_variance"), py::arg("forward_density") = kDefaultForwardDensity,
        py::arg("backscatter_density") = kDefaultBackscatterDensity, py::arg("table_samples") = 33,
        py::arg("caustic_width") = MarschnerCaustic{}.width, py::arg("caustic_fade_range") = MarschnerCaustic{}.fade_range,
        py::arg("caustic_max_window") = MarschnerCaustic{}.max_window, py::arg("m") = 4, py::arg("reference") = false,
        py::arg("theta_samples") = 256, py::arg("phi_samples") = 512,
        "Xu et al. 2011, Eq. 3-5 and 27-31: dual-scattering multiple scattering under SRBF lights per view "
        "direction, (global [M, 3], local [M, 3]); reference=True integrates the same model on a grid.");

    m.def(
        "bcsdf_bake",
        [](const HairParams& params, int theta_samples, int hair_count_samples, double max_hair_count,
           int table_samples, const std::vector<std::string>& sets) {
            for (const std::string& set : sets)
                if (set != "aggregated" && set != "xu")
                    throw Error("tables: unknown table set '" + set + "' (aggregated, xu)");
            const auto wants = [&](const char* set) { return std::find(sets.begin(), sets.end(), set) != sets.end(); };
            std::vector<BakedTable> tables;
            {
                py::gil_scoped_release release;
                BakeOptions options;
                options.theta_samples = theta_samples;
                options.hair_count_samples = hair_count_samples;
                options.max_hair_count = max_hair_count;
                options.table_samples = table_samples;
                if (wants("aggregated")) tables = bake_aggregated(params, options);
                if (wants("xu"))
                    for (BakedTable& t : bake_circular_gaussian(*default_circular_gaussian_tables()))
                        tables.push_back(std::move(t));
            }
            py::list result;
            for (const BakedTable& table : tables) {
                py::list axes;
                for (const BakeAxis& axis : table.axes) {
                    py::dict a;
                    a["name"] = axis.name;
                    a["range"] = py::make_tuple(axis.begin, axis.end);
                    a["samples"] = axis.samples;
                    if (axis.log_scale) a["scale"] = "log";
                    axes.append(a);
                }
                py::dict entry;
                entry["name"] = table.name;
                entry["equation"] = table.equation;
                entry["axes"] = axes;
                entry["channels"] = table.channels;
                py::array_t<float> values({py::ssize_t(table.height()), py::ssize_t(table.width()),
                                           static_cast<py::ssize_t>(table.channels.size())});
                std::copy(table.values.begin(), table.values.end(), values.mutable_data());
                entry["values"] = values;
                result.append(entry);
            }
            return result;
        },
        py::arg("params"), py::arg("theta_samples") = BakeOptions{}.theta_samples,
        py::arg("hair_count_samples") = BakeOptions{}.hair_count_samples,
        py::arg("max_hair_count") = BakeOptions{}.max_hair_count, py::arg("table_samples") = BakeOptions{}.table_samples,
        py::arg("tables") = std::vector<std::string>{"aggregated"},
        "Lookup tables of the aggregated BCSDF ('aggregated') and Xu et al. 2011's C_k, H_k ('xu'): a list of "
        "{name, equation, axes, channels, values [H, W, C] float32}.");

    m.def(
        "write_exr",
        [](const std::string& path, const FloatArray& values, const std::vector<std::string>& channels) {
            if (values.ndim() != 3 || values.shape(2) != static_cast<py::ssize_t>(channels.size()))
                throw Error(path + ": values must have shape [H, W, len(channels)]");
            const std::span<const float> data(values.data(), static_cast<size_t>(values.size()));
            py::gil_scoped_release release;
            write_exr(path, static_cast<int>(values.shape(1)), static_cast<int>(values.shape(0)), channels, data);
        },
        py::arg("path"), py::arg("values"), py::arg("channels"), "Writes float32 [H, W, C] as an OpenEXR image.");

    m.def(
        "bcsdf_dual_scattering",
        [](const std::string& model, const HairParams& params, const DoubleArray& theta_d, double backscatter_density,
           double tolerance) {
            if (theta_d.ndim() != 1) throw Error("theta_d must be one-dimensional");
            const std::span<const double> angles(theta_d.data(), static_cast<size_t>(theta_d.size()));
            std::vector<DualScatteringSample> table;
            {
                py::gil_scoped_release release;
                const auto bcsdf = make_bcsdf(parse_bcsdf_model(model), params);
                table = dual_scattering_table(*bcsdf, angles, backscatter_density, {tolerance, 10.0 * tolerance, 30});
            }
            const auto column = [&](glm::dvec3 DualScatteringSample::*field) {
                py::array_t<double> values({static_cast<py::ssize_t>(table.size()), py::ssize_t(3)});
                double* data = values.mutable_data();
                for (size_t k = 0; k < table.size(); ++k)
                    for (int c = 0; c < 3; ++c) data[3 * k + c] = (table[k].*field)[c];
                return values;
            };
            py::dict result;
            result["theta_d"] = py::array_t<double>(theta_d.size(), theta_d.data());
            result["a_f"] = column(&DualScatteringSample::a_f);
            result["a_b"] = column(&DualScatteringSample::a_b);
            result["alpha_f"] = column(&DualScatteringSample::alpha_f);
            result["alpha_b"] = column(&DualScatteringSample::alpha_b);
            result["beta_f"] = column(&DualScatteringSample::beta_f);
            result["beta_b"] = column(&DualScatteringSample::beta_b);
            result["A_1"] = column(&DualScatteringSample::A_1);
            result["A_3"] = column(&DualScatteringSample::A_3);
            result["A_b"] = column(&DualScatteringSample::A_b);
            result["delta_b"] = column(&DualScatteringSample::delta_b);
            result["sigma_b"] = column(&DualScatteringSample::sigma_b);
            return result;
        },
        py::arg("model"), py::arg("params"), py::arg("theta_d"), py::arg("backscatter_density") = kDefaultBackscatterDensity,
        py::arg("tolerance") = 1e-6, "Zinke et al. 2008 dual-scattering terms tabulated over theta_d ([K] and [K, 3]).");

    m.def(
        "chiang_far_field_table",
        [](const HairParams& params, int theta_samples, int phi_samples) {
            std::vector<glm::dvec3> table;
            std::array<LongitudinalLobe, 4> lobes{};
            {
                py::gil_scoped_release release;
                const ChiangBcsdf bcsdf(params);
                table = far_field_azimuthal_table(bcsdf, theta_samples, phi_samples);
                const auto shapes = bcsdf.lobe_shapes();
                std::copy(shapes.begin(), shapes.end(), lobes.begin());
            }
            py::array_t<double> values({py::ssize_t(4), py::ssize_t(theta_samples), py::ssize_t(phi_samples), py::ssize_t(3)});
            double* out = values.mutable_data();
            for (std::size_t k = 0; k < table.size(); ++k)
                for (int c = 0; c < 3; ++c) out[3 * k + c] = table[k][c];
            py::list shapes;
            for (const LongitudinalLobe& lobe : lobes) shapes.append(py::make_tuple(lobe.shift, lobe.variance));
            return py::make_tuple(values, shapes);
        },
        py::arg("params"), py::arg("theta_samples") = 64, py::arg("phi_samples") = 64,
        "The material's Chiang fibre in the far field for a shader: (values [4, theta_samples, phi_samples, 3], "
        "the lobes' (shift, variance)). values[p, j, k] is lobe p's (R, TT, TRT, TRRT+) weight times its "
        "azimuthal part N_p at theta_o = (pi / 2) j / (theta_samples - 1) and phi = pi k / (phi_samples - 1); "
        "the fibre is sum_p M_p(theta_i, theta_o) values[p] / cos(theta_i).");

    m.def("fiber_rtd_lobes", [](const HairParams& params) {
        const FiberRtdBcsdf fiber(params);
        const auto lobes = fiber.lobe_shapes();
        py::dict d;
        d["r_shift"] = lobes[0].shift;
        d["r_variance"] = lobes[0].variance;
        d["tt_shift"] = lobes[1].shift;
        d["tt_variance"] = lobes[1].variance;
        d["tt_azimuthal_variance"] = fiber.azimuthal_variance();
        return d;
    }, py::arg("params"), "Lobe shapes of the R/TT/D fibre (Huang et al. 2025, Eq. 8): what a shader needs besides the baked tables.");
}

}  // namespace hairlod::python
