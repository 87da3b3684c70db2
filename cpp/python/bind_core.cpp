// Strands: the C++ StrandSet with zero-copy numpy views of its arrays.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <string>

#include "bindings.h"
#include "numpy_arrays.h"
#include "hairlod/core/error.h"
#include "hairlod/core/strand_density.h"
#include "hairlod/core/strand_metrics.h"
#include "hairlod/core/strand_set.h"
#include "hairlod/curves/resample.h"

namespace py = pybind11;

namespace hairlod::python {

namespace {

using IndexArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

AttributeDomain parse_domain(const std::string& domain) {
    if (domain == "point") return AttributeDomain::Point;
    if (domain == "curve") return AttributeDomain::Curve;
    throw Error("attribute domain must be 'point' or 'curve', got '" + domain + "'");
}

std::vector<glm::vec3> points_from_array(const FloatArray& points) {
    const std::span<const glm::vec3> rows = rows_of<glm::vec3>(points, 3, "points");
    return {rows.begin(), rows.end()};
}

std::vector<float> floats_from_array(const FloatArray& values, const char* what) {
    if (values.ndim() != 1) throw Error(std::string(what) + " must be one-dimensional");
    return {values.data(), values.data() + values.size()};
}

std::vector<float> radius_or_zero(const std::optional<FloatArray>& radius, size_t point_count) {
    return radius ? floats_from_array(*radius, "radius") : std::vector<float>(point_count, 0.0f);
}

StrandSet make_strands(const FloatArray& points, const IndexArray& offsets,
                       const std::optional<FloatArray>& radius) {
    StrandSet strands;
    strands.points = points_from_array(points);
    if (offsets.ndim() != 1) throw Error("offsets must be one-dimensional");
    strands.offsets.assign(offsets.data(), offsets.data() + offsets.size());
    strands.radius = radius_or_zero(radius, strands.points.size());
    strands.validate();
    return strands;
}

// A numpy array over memory owned by `owner`, which the array keeps alive.
template <typename T>
py::array view(const T* data, std::vector<py::ssize_t> shape, const py::object& owner, bool writable) {
    py::array result(py::dtype::of<T>(), std::move(shape), {}, data, owner);
    if (!writable) result.attr("flags").attr("writeable") = false;
    return result;
}

void copy_into(std::span<float> target, const FloatArray& source, const char* what) {
    if (static_cast<size_t>(source.size()) != target.size())
        throw Error(std::string(what) + " needs " + std::to_string(target.size()) + " values, got " +
                    std::to_string(source.size()));
    std::memcpy(target.data(), source.data(), target.size() * sizeof(float));
}

}  // namespace

void bind_core(py::module_& m) {
    py::class_<StrandSet>(m, "Strands", R"doc(
Hair strands as a structure of arrays.

points  float32 [N, 3]   (zero-copy view, writable in place)
offsets int64 [C + 1]    curve c owns points[offsets[c]:offsets[c + 1]] (read-only view)
radius  float32 [N]      (zero-copy view, writable in place)
Named float attributes live on the 'point' or 'curve' domain with 1 or more components.
len(strands) is the number of curves C.)doc")
        .def(py::init(&make_strands), py::arg("points"), py::arg("offsets"), py::arg("radius") = py::none(),
             "Strands from points [N, 3], offsets [C + 1] and optional radius [N] (default 0); validated.")
        .def_static(
            "from_counts",
            [](const FloatArray& points, const IndexArray& counts, const std::optional<FloatArray>& radius) {
                if (counts.ndim() != 1) throw Error("counts must be one-dimensional");
                std::vector<glm::vec3> p = points_from_array(points);
                const size_t n = p.size();
                return strands_from_counts(std::move(p), {counts.data(), static_cast<size_t>(counts.size())},
                                           radius_or_zero(radius, n));
            },
            py::arg("points"), py::arg("counts"), py::arg("radius") = py::none(),
            "Strands from points [N, 3] and the number of points of each curve.")
        .def("__len__", &StrandSet::curve_count)
        .def("__repr__",
             [](const StrandSet& s) {
                 return "Strands(curves=" + std::to_string(s.curve_count()) +
                        ", points=" + std::to_string(s.point_count()) + ")";
             })
        .def_property_readonly("curve_count", &StrandSet::curve_count)
        .def_property_readonly("point_count", &StrandSet::point_count)
        .def_property(
            "points",
            [](py::object self) {
                const auto& s = self.cast<const StrandSet&>();
                return view(point_floats(s.points).data(), {static_cast<py::ssize_t>(s.point_count()), 3}, self, true);
            },
            [](StrandSet& s, const FloatArray& points) {
                copy_into(point_floats(s.points), points, "points");
            })
        .def_property_readonly("offsets",
                               [](py::object self) {
                                   const auto& s = self.cast<const StrandSet&>();
                                   return view(s.offsets.data(), {static_cast<py::ssize_t>(s.offsets.size())},
                                               self, false);
                               })
        .def_property(
            "radius",
            [](py::object self) {
                const auto& s = self.cast<const StrandSet&>();
                return view(s.radius.data(), {static_cast<py::ssize_t>(s.radius.size())}, self, true);
            },
            [](StrandSet& s, const FloatArray& radius) { copy_into(s.radius, radius, "radius"); })
        .def("counts",
             [](const StrandSet& s) {
                 py::array_t<int64_t> counts(static_cast<py::ssize_t>(s.curve_count()));
                 auto out = counts.mutable_unchecked<1>();
                 for (size_t c = 0; c < s.curve_count(); ++c) out(c) = static_cast<int64_t>(s.curve_size(c));
                 return counts;
             },
             "Number of points of each curve, int64 [C].")
        .def(
            "set_attribute",
            [](StrandSet& s, const std::string& name, const FloatArray& values, const std::string& domain) {
                if (values.ndim() < 1 || values.ndim() > 2)
                    throw Error("attribute '" + name + "' must have shape [n] or [n, k]");
                const int components = values.ndim() == 2 ? static_cast<int>(values.shape(1)) : 1;
                s.set_attribute(name, parse_domain(domain), components,
                                {values.data(), values.data() + values.size()});
            },
            py::arg("name"), py::arg("values"), py::arg("domain") = "point",
            "Adds or replaces a float attribute: values [n] or [n, k], n = points or curves.")
        .def(
            "attribute",
            [](const StrandSet& s, const std::string& name) {
                const Attribute* attribute = s.find_attribute(name);
                if (!attribute) throw py::key_error("no attribute named '" + name + "'");
                const auto rows = static_cast<py::ssize_t>(attribute->values.size() / attribute->components);
                std::vector<py::ssize_t> shape{rows};
                if (attribute->components > 1) shape.push_back(attribute->components);
                // A copy: replacing the attribute later must not leave a dangling view.
                py::array_t<float> result(shape);
                std::memcpy(result.mutable_data(), attribute->values.data(), attribute->values.size() * sizeof(float));
                return result;
            },
            py::arg("name"), "A copy of the attribute's values, shape [n] or [n, k].")
        .def("attribute_names", [](const StrandSet& s) {
            std::vector<std::string> names;
            for (const auto& entry : s.attributes) names.push_back(entry.first);
            return names;
        })
        .def("attribute_domain",
             [](const StrandSet& s, const std::string& name) {
                 const Attribute* attribute = s.find_attribute(name);
                 if (!attribute) throw py::key_error("no attribute named '" + name + "'");
                 return std::string(attribute->domain == AttributeDomain::Point ? "point" : "curve");
             })
        .def("remove_attribute", [](StrandSet& s, const std::string& name) {
            if (s.attributes.erase(name) == 0) throw py::key_error("no attribute named '" + name + "'");
        })
        .def("validate", &StrandSet::validate, "Raises ValueError naming the first problem.")
        .def("copy", [](const StrandSet& s) { return StrandSet(s); })
        .def("bounding_box",
             [](const StrandSet& s) {
                 const Bounds3 box = bounding_box(s.points);
                 return py::make_tuple(py::array_t<float>(3, &box.lower.x), py::array_t<float>(3, &box.upper.x));
             },
             "(lower, upper) corners, float32 [3] each.")
        .def("curve_lengths",
             [](const StrandSet& s) {
                 std::vector<double> lengths;
                 {
                     py::gil_scoped_release release;
                     lengths = curve_lengths(s);
                 }
                 return py::array_t<double>(static_cast<py::ssize_t>(lengths.size()), lengths.data());
             },
             "Length of each curve's control polyline, float64 [C].")
        .def("resampled",
             [](const StrandSet& s, int points_per_curve, int subdivisions_per_segment) {
                 py::gil_scoped_release release;
                 return resample_strands(s, ResampleOptions{points_per_curve, subdivisions_per_segment});
             },
             py::arg("points_per_curve"), py::arg("subdivisions_per_segment") = ResampleOptions{}.subdivisions_per_segment,
             "Each curve resampled to K points equally spaced in arc length along its centripetal "
             "Catmull-Rom curve, measured on a polyline of `subdivisions_per_segment` pieces per segment.")
        .def("require_float_range", &StrandSet::require_float_range, py::arg("what"),
             "Raises ValueError ('what: ...') when coordinates or radii exceed 1e13 in magnitude or the hair "
             "is less than 1e-10 across: the range hairlod's float32 geometry handles.");

    m.def("strand_density",
          [](const FloatArray& points, const IndexArray& offsets, const FloatArray& radius, const DoubleArray& lower,
             const DoubleArray& upper, int resolution, int64_t max_samples, double sample_spacing) {
              const std::span<const glm::vec3> point_rows = rows_of<glm::vec3>(points, 3, "points");
              if (offsets.ndim() != 1) throw Error("offsets must be one-dimensional");
              if (radius.ndim() != 1) throw Error("radius must be one-dimensional");
              if (lower.size() != 3 || upper.size() != 3) throw Error("lower and upper must hold 3 values each");
              StrandDensityOptions options;
              options.lower = {lower.data()[0], lower.data()[1], lower.data()[2]};
              options.upper = {upper.data()[0], upper.data()[1], upper.data()[2]};
              options.resolution = resolution;
              options.max_samples = max_samples;
              options.sample_spacing = sample_spacing;
              StrandDensity density;
              {
                  py::gil_scoped_release release;
                  density = strand_density(point_rows, {offsets.data(), static_cast<size_t>(offsets.size())},
                                           {radius.data(), static_cast<size_t>(radius.size())}, options);
              }
              py::array_t<double> fields = to_numpy<double>(
                  density.fields, {kStrandDensityFields, density.shape[0], density.shape[1], density.shape[2]});
              return py::make_tuple(fields, density.voxel, density.strand_step);
          },
          py::arg("points"), py::arg("offsets"), py::arg("radius"), py::arg("lower"), py::arg("upper"),
          py::arg("resolution"), py::arg("max_samples"), py::arg("sample_spacing"),
          "(fields float64 [7, nx, ny, nz], voxel, strand_step): the strands' projected area per unit volume and "
          "its tangent-weighted second moments on a grid over the box [lower, upper] with one voxel of margin "
          "on every side (core/strand_density.h).");
}

}  // namespace hairlod::python
