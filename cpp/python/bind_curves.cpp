// Curves attached to a surface (curves/surface_attachment.h): numpy arrays in, per-curve transforms out.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "numpy_arrays.h"
#include "hairlod/core/error.h"
#include "hairlod/curves/surface_attachment.h"

namespace py = pybind11;

namespace hairlod::python {

namespace {

std::span<const int32_t> ints_of(const IntArray& values, const char* what) {
    if (values.ndim() != 1) throw Error(std::string(what) + " must be one-dimensional");
    return {values.data(), static_cast<size_t>(values.size())};
}

std::span<const glm::ivec3> triangles_of(const IntArray& values) {
    if (values.ndim() != 2 || values.shape(1) != 3) throw Error("triangles must have shape [T, 3]");
    return {reinterpret_cast<const glm::ivec3*>(values.data()), static_cast<size_t>(values.shape(0))};
}

}  // namespace

void bind_curves(py::module_& m) {
    py::class_<SurfaceFollow>(m, "SurfaceFollow",
                              "Curves attached to a triangle mesh by UV coordinates, moved rigidly with their root "
                              "triangles' frames as Blender's Deform Curves on Surface moves them.")
        .def(py::init([](const FloatArray& root_uvs, const FloatArray& corner_uvs, const IntArray& triangles,
                         const IntArray& corner_verts, const FloatArray& positions, const FloatArray& corner_normals,
                         const FloatArray& surface_to_curves) {
                 const auto tris = triangles_of(triangles);
                 const auto roots = rows_of<glm::vec2>(root_uvs, 2, "root_uvs");
                 const auto uvs = rows_of<glm::vec2>(corner_uvs, 2, "corner_uvs");
                 const SurfaceMesh rest{rows_of<glm::vec3>(positions, 3, "positions"), ints_of(corner_verts, "corner_verts"), tris,
                                        rows_of<glm::vec3>(corner_normals, 3, "corner_normals")};
                 if (uvs.size() != rest.corner_verts.size())
                     throw Error("corner_uvs has " + std::to_string(uvs.size()) + " rows, corner_verts " +
                                 std::to_string(rest.corner_verts.size()));
                 const glm::mat4 matrix = matrix_from(surface_to_curves, "surface_to_curves");
                 py::gil_scoped_release release;
                 return SurfaceFollow(bind_by_uv(roots, uvs, tris), rest, matrix);
             }),
             py::arg("root_uvs"), py::arg("corner_uvs"), py::arg("triangles"), py::arg("corner_verts"), py::arg("positions"),
             py::arg("corner_normals"), py::arg("surface_to_curves"),
             "Binds curves by their root UV coordinates [N, 2] to the mesh's UV map (corner_uvs [C, 2]), triangles "
             "[T, 3] (corner indices), corner_verts [C], at the pose of positions [V, 3] and corner_normals [C, 3]; "
             "surface_to_curves [4, 4] maps the mesh's object space into the curves' (numpy rows are matrix rows).")
        .def_property_readonly("bound", [](const SurfaceFollow& f) {
            py::array_t<bool> result(static_cast<py::ssize_t>(f.curve_count()));
            for (size_t i = 0; i < f.curve_count(); ++i) result.mutable_at(static_cast<py::ssize_t>(i)) = f.is_bound(i);
            return result;
        }, "bool [N]: the curves that move with the surface (a root triangle and a proper frame).")
        .def("transforms", [](const SurfaceFollow& f, const FloatArray& positions, const FloatArray& corner_normals,
                              const FloatArray& surface_to_curves, std::optional<py::array> out) -> py::array {
            const auto points = rows_of<glm::vec3>(positions, 3, "positions");
            const auto normals = rows_of<glm::vec3>(corner_normals, 3, "corner_normals");
            const glm::mat4 matrix = matrix_from(surface_to_curves, "surface_to_curves");
            const auto curves = static_cast<py::ssize_t>(f.curve_count());
            if (!out) {
                std::vector<glm::vec4> rows;
                {
                    py::gil_scoped_release release;
                    rows = f.transforms(points, normals, matrix);
                }
                return moved_to_numpy<float>(std::move(rows), {curves, 3, 4});
            }
            float* data = output_data<float>(*out, {curves, 3, 4}, "out");
            const std::span<glm::vec4> rows(reinterpret_cast<glm::vec4*>(data), static_cast<size_t>(3 * curves));
            {
                py::gil_scoped_release release;
                f.transforms(points, normals, matrix, rows);
            }
            return *out;
        }, py::arg("positions"), py::arg("corner_normals"), py::arg("surface_to_curves"), py::arg("out") = py::none(),
           "float32 [N, 3, 4]: per curve the affine map [R | t] (rows) from its rest pose to the pose of the same "
           "mesh with these positions [V, 3] and corner normals [C, 3]; the identity for a curve that does not move "
           "with it. With `out` (float32, C-contiguous, [N, 3, 4]) they are written there and `out` is returned.");
}

}  // namespace hairlod::python
