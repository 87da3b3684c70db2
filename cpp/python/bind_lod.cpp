// LodAsset, LodGeometry and Selection: copies out as numpy arrays, the GIL released in long calls.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>

#include <algorithm>
#include <cstring>
#include <string>
#include <type_traits>

#include "bindings.h"
#include "numpy_arrays.h"
#include "hairlod/core/error.h"
#include "hairlod/lod/lod_asset.h"
#include "hairlod/lod/preview_vertices.h"
#include "hairlod/lod/selection.h"
#include "hairlod/lod/skinning.h"
#include "hairlod/lod/vertex_lod.h"
#include "hairlod/lod/view_selection.h"

namespace py = pybind11;

namespace hairlod::python {

namespace {


// A numpy copy of `values` reshaped to `shape` (the element type's components form the last axes).
py::ssize_t as_size(size_t n) { return static_cast<py::ssize_t>(n); }

py::dict level_dict(const LodAsset& asset, size_t level_index, const ThickHairGeometry& rest) {
    const ThickHairLevel& level = asset.thick_levels[level_index];
    const size_t nc = static_cast<size_t>(asset.control_points);
    std::vector<int32_t> n_total(level.hair_count());
    std::vector<glm::vec3> major_axis(level.hair_count() * nc), minor_axis(major_axis.size());
    std::vector<glm::vec2> radii(major_axis.size());
    for (size_t h = 0; h < n_total.size(); ++h) {
        n_total[h] = level.n_total(h);
        for (size_t k = 0; k < nc; ++k) {
            const RestSection section = asset.section(level_index, h, k);
            major_axis[h * nc + k] = section.major_axis;
            minor_axis[h * nc + k] = section.minor_axis;
            radii[h * nc + k] = section.radii;
        }
    }
    const auto hairs = as_size(level.hair_count()), nc_size = as_size(nc);
    py::dict d;
    d["centres"] = to_numpy<float>(rest.centre, {hairs, nc_size, 3});
    d["major_axis"] = to_numpy<float>(major_axis, {hairs, nc_size, 3});
    d["minor_axis"] = to_numpy<float>(minor_axis, {hairs, nc_size, 3});
    d["radii"] = to_numpy<float>(radii, {hairs, nc_size, 2});
    d["density"] = to_numpy<float>(asset.density(level_index), {hairs, nc_size});
    d["n_total"] = to_numpy<int32_t>(n_total, {hairs});
    d["parent"] = to_numpy<int32_t>(level.parent, {hairs});
    d["membership"] = to_numpy<int32_t>(asset.strand_hairs(level_index), {as_size(asset.strand_count())});
    d["cluster_first"] = to_numpy<int32_t>(level.cluster_first, {as_size(level.cluster_first.size())});
    d["coverage"] = level.coverage;
    d["mean_area"] = level.mean_area;
    return d;
}

py::dict geometry_dict(const LodAsset& asset, LodGeometry geometry) {
    const auto nc = static_cast<py::ssize_t>(asset.control_points);
    py::dict d;
    py::list levels;
    for (const ThickHairGeometry& g : geometry.levels) {
        const auto hairs = as_size(g.centre.size()) / nc;
        py::dict level;
        level["centres"] = to_numpy<float>(g.centre, {hairs, nc, 3});
        level["tangents"] = to_numpy<float>(g.tangent, {hairs, nc, 3});
        level["major"] = to_numpy<float>(g.major, {hairs, nc, 3});
        level["minor"] = to_numpy<float>(g.minor, {hairs, nc, 3});
        level["corners"] = to_numpy<float>(g.corners, {hairs, nc, 4, 3});
        levels.append(level);
    }
    d["levels"] = levels;
    d["cluster_bounds"] = to_numpy<float>(geometry.cluster_bounds, {as_size(geometry.cluster_bounds.size()), 4});
    d["strands"] = py::cast(std::move(geometry.strands));
    return d;
}

// Element type of a stored asset array -> numpy scalar type and components per element.
template <typename T>
struct Stored {
    using Scalar = T;
    static constexpr py::ssize_t components = 1;
};
template <glm::length_t N, typename T>
struct Stored<glm::vec<N, T>> {
    using Scalar = T;
    static constexpr py::ssize_t components = N;
};
template <>
struct Stored<QuantisationBox> {  // lower xyz, step xyz
    using Scalar = float;
    static constexpr py::ssize_t components = 6;
};
template <size_t N>
struct Stored<std::array<int32_t, N>> {
    using Scalar = int32_t;
    static constexpr py::ssize_t components = N;
};
template <>
struct Stored<FrameKind> {
    using Scalar = uint8_t;
    static constexpr py::ssize_t components = 1;
};

// A stored array as numpy: [n] for scalars, [n, components] otherwise.
template <typename T>
py::array stored_to_numpy(const std::vector<T>& values) {
    using S = Stored<T>;
    std::vector<py::ssize_t> shape{as_size(values.size())};
    if (S::components > 1) shape.push_back(S::components);
    return to_numpy<typename S::Scalar>(values, shape);
}

template <typename T>
void stored_from_numpy(const py::handle& source, const std::string& name, std::vector<T>& values) {
    using S = Stored<T>;
    const auto array = py::array_t<typename S::Scalar, py::array::c_style>::ensure(source);
    if (!array) throw Error("LoD asset: " + name + " must be an array of " + py::str(py::dtype::of<typename S::Scalar>()).cast<std::string>());
    const bool scalar_rows = S::components == 1;
    if (array.ndim() != (scalar_rows ? 1 : 2) || (!scalar_rows && array.shape(1) != S::components))
        throw Error("LoD asset: " + name + " must have shape [n" + (scalar_rows ? "" : ", " + std::to_string(S::components)) + "]");
    values.resize(static_cast<size_t>(array.shape(0)));
    static_assert(std::is_trivially_copyable_v<T>);
    std::memcpy(static_cast<void*>(values.data()), array.data(), values.size() * sizeof(T));
}

py::dict asset_arrays(const LodAsset& asset, bool sections) {
    py::dict arrays;
    LodAsset::visit_arrays(asset, [&](const char* name, const auto& values) { arrays[name] = stored_to_numpy(values); });
    py::list levels;
    for (const ThickHairLevel& level : asset.thick_levels) {
        py::dict d;
        const auto add = [&](const char* name, const auto& values) { d[name] = stored_to_numpy(values); };
        ThickHairLevel::visit_hierarchy_arrays(level, add);
        if (sections) ThickHairLevel::visit_section_arrays(level, add);
        levels.append(d);
    }
    arrays["levels"] = levels;
    return arrays;
}

py::dict asset_scalars(const LodAsset& asset) {
    py::dict d;
    d["control_points"] = asset.control_points;
    d["radius_exponent"] = asset.radius_exponent;
    d["ellipse_coverage"] = asset.ellipse_coverage;
    py::list coverage, mean_area;
    for (const ThickHairLevel& level : asset.thick_levels) {
        coverage.append(level.coverage);
        mean_area.append(level.mean_area);
    }
    d["coverage"] = coverage;
    d["mean_area"] = mean_area;
    return d;
}

LodAsset asset_from(const py::dict& scalars, const py::dict& arrays) {
    LodAsset asset;
    try {
        asset.control_points = scalars["control_points"].cast<int>();
        asset.radius_exponent = scalars["radius_exponent"].cast<int>();
        if (scalars.contains("ellipse_coverage")) asset.ellipse_coverage = scalars["ellipse_coverage"].cast<float>();
        LodAsset::visit_arrays(asset, [&](const char* name, auto& values) { stored_from_numpy(arrays[name], name, values); });
        const py::list levels = arrays["levels"];
        const py::list coverage = scalars["coverage"], mean_area = scalars["mean_area"];
        if (coverage.size() != levels.size() || mean_area.size() != levels.size())
            throw Error("LoD asset: coverage and mean_area need one value per level");
        for (size_t l = 0; l < levels.size(); ++l) {
            ThickHairLevel& level = asset.thick_levels.emplace_back();
            const py::dict d = levels[l];
            const std::string name = "level " + std::to_string(l) + " ";
            ThickHairLevel::visit_hierarchy_arrays(level, [&](const char* array, auto& values) {
                stored_from_numpy(d[array], name + array, values);
            });
            // Every level has its cross-sections, or none has (they are then fitted again below).
            const bool has_sections = d.contains("centre_offset");
            if (l > 0 && has_sections != !asset.thick_levels[0].centre_offset.empty())
                throw Error("LoD asset: either every level stores its cross-sections or none does");
            if (has_sections)
                ThickHairLevel::visit_section_arrays(level, [&](const char* array, auto& values) {
                    stored_from_numpy(d[array], name + array, values);
                });
            level.coverage = coverage[l].cast<double>();
            level.mean_area = mean_area[l].cast<double>();
        }
    } catch (const py::error_already_set& error) {
        throw Error(std::string("LoD asset: missing or malformed entry: ") + error.what());
    } catch (const py::cast_error& error) {
        throw Error(std::string("LoD asset: malformed entry: ") + error.what());
    }
    if (asset.thick_levels.empty() || asset.thick_levels[0].centre_offset.empty()) {
        py::gil_scoped_release release;
        asset.validate_structure();
        fit_sections(asset);
    }
    asset.validate();
    return asset;
}

std::vector<glm::vec3> guides_from(const FloatArray& guides, const LodAsset& asset) {
    if (guides.ndim() != 3 || static_cast<size_t>(guides.shape(0)) != asset.guide_count() ||
        guides.shape(1) != asset.control_points || guides.shape(2) != 3)
        throw Error("deformed guides must have shape [" + std::to_string(asset.guide_count()) + ", " +
                    std::to_string(asset.control_points) + ", 3]");
    std::vector<glm::vec3> points(asset.rest_guides.size());
    std::memcpy(points.data(), guides.data(), points.size() * sizeof(glm::vec3));
    return points;
}

}  // namespace

void bind_lod(py::module_& m) {
    m.attr("DEFAULT_WIDTH_PX") = kDefaultWidthPx;
    const LodOptions defaults;
    py::dict lod_defaults;
    lod_defaults["guides"] = defaults.guides;
    lod_defaults["levels"] = defaults.levels;
    lod_defaults["control_points"] = defaults.control_points;
    lod_defaults["seed"] = defaults.seed;
    lod_defaults["ellipse_coverage"] = defaults.ellipse_coverage;
    m.attr("LOD_DEFAULTS") = lod_defaults;
    m.attr("LEVELS_RANGE") = py::make_tuple(kMinLevels, kMaxLevels);
    m.attr("MIN_CONTROL_POINTS") = kMinControlPoints;
    // Strands.resampled(K, LOD_ARC_LENGTH_SUBDIVISIONS) resamples as build_lod does (the rest pose skinning reproduces).
    m.attr("LOD_ARC_LENGTH_SUBDIVISIONS") = LodOptions{}.arc_length_subdivisions;
    m.attr("MIN_WIDTH_PX") = kMinWidthPx;
    m.attr("SKIN_MAP_TEXELS") = kMapTexels;
    py::class_<Selection>(m, "Selection", "LoD level per L0 cluster and segment, visibility and draw ranges.")
        .def_property_readonly("levels",
                               [](const Selection& s) {
                                   return to_numpy<uint8_t>(s.level, {as_size(s.visible.size()), static_cast<py::ssize_t>(s.segments)});
                               })
        .def_property_readonly("visible", [](const Selection& s) { return to_numpy<uint8_t>(s.visible, {as_size(s.visible.size())}).attr("astype")("bool"); })
        .def_property_readonly("draws", [](const Selection& s) {
            // Columns: level, cluster, first, count, first_segment, segment_count.
            return to_numpy<int32_t>(s.draws, {as_size(s.draws.size()), 6});
        });

    py::class_<LodAsset>(m, "LodAsset", "Guides, L0 clusters, thick-hair levels and skinning coordinates.")
        .def_readonly("control_points", &LodAsset::control_points)
        .def_property_readonly("guide_count", &LodAsset::guide_count)
        .def_property_readonly("cluster_count", &LodAsset::cluster_count)
        .def_property_readonly("strand_count", &LodAsset::strand_count)
        .def_property_readonly("level_count", &LodAsset::level_count)
        .def_property_readonly("memory_bytes", &LodAsset::memory_bytes)
        .def_property_readonly("stored_bytes", &LodAsset::stored_bytes)
        .def_property_readonly("guide_strands", [](const LodAsset& a) { return to_numpy<int64_t>(a.guide_strands, {as_size(a.guide_strands.size())}); })
        .def_property_readonly("strand_order", [](const LodAsset& a) { return to_numpy<int32_t>(a.strand_order, {as_size(a.strand_order.size())}); },
                               "int32 [strands]: the strands in hierarchy order (the preview's and the levels' order).")
        .def_property_readonly("rest_guides", [](const LodAsset& a) {
            return to_numpy<float>(a.rest_guides, {as_size(a.guide_count()), static_cast<py::ssize_t>(a.control_points), 3});
        })
        .def_property_readonly("cluster_guides", [](const LodAsset& a) { return to_numpy<int32_t>(a.cluster_guides, {as_size(a.cluster_count()), 3}); })
        .def_property_readonly("timings", [](const LodAsset& a) {
            const LodBuildTimings& t = a.timings;
            py::dict d;
            d["resample"] = t.resample;
            d["kmeans"] = t.kmeans;
            d["clusters"] = t.clusters;
            d["levels"] = t.levels;
            d["fitting"] = t.fitting;
            d["weights"] = t.weights;
            return d;
        })
        .def("thick_levels", [](const LodAsset& a) {
            LodGeometry rest;
            {
                py::gil_scoped_release release;
                rest = a.rest_geometry();
            }
            py::list levels;
            for (size_t l = 0; l < a.thick_levels.size(); ++l) levels.append(level_dict(a, l, rest.levels[l]));
            return levels;
        }, "Per thick level: rest centres, decoded axes and radii, density, n_total, parent, membership, coverage.")
        .def("arrays", &asset_arrays, py::arg("sections") = true,
             "Every array by name (flat [n] or [n, components]); 'levels' holds one dict per thick level, with its "
             "cross-sections unless sections is False (from_arrays fits them again from the strands: fit_sections).")
        .def("scalars", &asset_scalars, "control_points, radius_exponent, ellipse_coverage, and coverage and mean_area per thick level.")
        .def_static("from_arrays", &asset_from, py::arg("scalars"), py::arg("arrays"),
                    "Rebuilds an asset from scalars() and arrays(); raises ValueError naming an inconsistent array.")
        .def("with_levels", [](const LodAsset& a, const std::vector<size_t>& kept) { return a.with_levels(kept); },
             py::arg("kept"), "A copy keeping the thick levels at positions `kept` (increasing), parents composed.")
        .def("skinning_rest", [](const LodAsset& a) {
            py::gil_scoped_release release;
            return skinning_rest(a);
        }, "What skinning derives once from the rest pose (prism frames, stencils), for skin(..., rest).")
        .def("skin", [](const LodAsset& a, const FloatArray& guides, const SkinningRest* rest) {
            const std::vector<glm::vec3> points = guides_from(guides, a);
            LodGeometry geometry;
            {
                py::gil_scoped_release release;
                geometry = rest != nullptr ? skin_geometry(a, *rest, points) : a.skin(points);
            }
            return geometry_dict(a, std::move(geometry));
        }, py::arg("deformed_guides"), py::arg("rest") = py::none(),
           "Skinned strands and thick hairs for guides [G, n_c, 3]; `rest` from skinning_rest() saves deriving it.")
        .def("rest_geometry", [](const LodAsset& a) {
            LodGeometry geometry;
            {
                py::gil_scoped_release release;
                geometry = a.rest_geometry();
            }
            return geometry_dict(a, std::move(geometry));
        }, "The strands and thick hairs at the rest pose, as skin() returns them (decoded, not skinned).")
        .def("preview_vertices", [](const LodAsset& a) {
            PreviewVertices v;
            {
                py::gil_scoped_release release;
                v = preview_vertices(a);
            }
            auto rows = [](auto& values) {
                using Value = std::decay_t<decltype(values[0])>;
                const py::ssize_t count = as_size(values.size());
                return moved_to_numpy<float>(std::move(values), {count, static_cast<py::ssize_t>(Value::length())});
            };
            py::list levels;
            for (ThickStripVertices& level : v.levels) {
                py::dict d;
                d["position"] = rows(level.position);
                d["tangent"] = rows(level.tangent);
                d["major"] = rows(level.major);
                d["minor"] = rows(level.minor);
                d["cluster"] = rows(level.cluster);
                d["select_key"] = rows(level.select_key);
                levels.append(d);
            }
            py::dict strands;
            strands["position"] = rows(v.strands.position);
            strands["tangent"] = rows(v.strands.tangent);
            strands["select_key"] = rows(v.strands.select_key);
            py::dict d;
            d["levels"] = levels;
            d["strands"] = strands;
            d["rest_strands"] = py::cast(std::move(v.rest_strands));
            return d;
        }, "Rest-pose vertex arrays of the viewport preview (lod/preview_vertices.h): per thick level strip "
           "vertices (position, tangent, major, minor, cluster, select_key), the strands' line vertices in "
           "hierarchy order (position, tangent, select_key), and the decoded rest strands.")
        .def("resample_guides", [](const LodAsset& a, const StrandSet& curves) {
            std::vector<glm::vec3> points;
            {
                py::gil_scoped_release release;
                points = resample_guides(a, curves);
            }
            return to_numpy<float>(points, {as_size(a.guide_count()), static_cast<py::ssize_t>(a.control_points), 3});
        }, py::arg("guide_curves"), "The guides [G, n_c, 3] from the guide strands as they are now, resampled as build_lod does.")
        .def("time_selection", [](const LodAsset& a, const FloatArray& view, const FloatArray& projection,
                                  std::pair<float, float> viewport, float width_px, int frames) {
            const Camera camera{matrix_from(view, "view"), matrix_from(projection, "projection"), {viewport.first, viewport.second}};
            py::gil_scoped_release release;
            return median_deferred_step_seconds(a, a.rest_geometry(), camera, width_px, frames);
        }, py::arg("view"), py::arg("projection"), py::arg("viewport_size"), py::arg("width_px") = kDefaultWidthPx, py::arg("frames") = 100,
           "Median seconds of one Huang 2025 Eq. 16 frame (skinning excluded) at the rest pose, for benchmarks.")
        .def("select", [](const LodAsset& a, const std::optional<FloatArray>& guides, const FloatArray& view, const FloatArray& projection,
                          std::pair<float, float> viewport, float width_px, const Selection* previous, const SkinningRest* rest) {
            const std::vector<glm::vec3> points = guides ? guides_from(*guides, a) : std::vector<glm::vec3>{};
            const Camera camera{matrix_from(view, "view"), matrix_from(projection, "projection"), {viewport.first, viewport.second}};
            py::gil_scoped_release release;
            const LodGeometry geometry = !guides         ? a.rest_geometry()
                                         : rest != nullptr ? skin_geometry(a, *rest, points)
                                                           : a.skin(points);
            return previous ? select_deferred(a, geometry, camera, width_px, *previous)
                            : select_initial(a, geometry, camera, width_px);
        }, py::arg("guides"), py::arg("view"), py::arg("projection"), py::arg("viewport_size"), py::arg("width_px") = kDefaultWidthPx,
           py::arg("previous") = py::none(), py::arg("rest") = py::none(),
           "Initial selection (Sec. 5.1 step 5), or Huang 2025 Eq. 16 from `previous`, for guides [G, n_c, 3] "
           "or the rest pose (None).");

    py::class_<SkinningRest>(m, "SkinningRest",
                             "What skinning derives from an asset's rest pose (LodAsset.skinning_rest); opaque.");

    py::class_<FrameSkinning>(m, "FrameSkinning",
                              "Per-frame skinning for GPU renderers: the quadratic map of each L0 cluster and control point, "
                              "and the geometry LoD selection reads (Sec. 5.1 step 4).")
        .def(py::init([](const LodAsset& a) {
                 py::gil_scoped_release release;
                 return FrameSkinning(a);
             }),
             py::arg("asset"), py::keep_alive<1, 2>())
        .def("update", [](FrameSkinning& s, const FloatArray& guides) {
            const std::vector<glm::vec3> points = guides_from(guides, s.asset());
            py::gil_scoped_release release;
            s.update(points);
        }, py::arg("deformed_guides"), "Skins to guides [G, n_c, 3]; raises ValueError on bad guides (keeping the last frame).")
        .def_property_readonly("maps", [](const FrameSkinning& s) {
            const auto clusters = as_size(s.asset().cluster_count()), nc = static_cast<py::ssize_t>(s.asset().control_points);
            return to_numpy<float>(s.maps(), {clusters, nc, static_cast<py::ssize_t>(kMapTexels), 4});
        }, "float32 [clusters, n_c, SKIN_MAP_TEXELS, 4]: the maps as the preview's shader reads them (hairlod.lod.apply_maps).")
        .def("maps_into", [](const FrameSkinning& s, py::array out) {
            const auto clusters = as_size(s.asset().cluster_count()), nc = static_cast<py::ssize_t>(s.asset().control_points);
            float* data = output_data<float>(out, {clusters, nc, static_cast<py::ssize_t>(kMapTexels), 4}, "out");
            std::memcpy(data, s.maps().data(), s.maps().size() * sizeof(s.maps()[0]));
            return out;
        }, py::arg("out"), "The maps written into `out` (float32, C-contiguous [clusters, n_c, SKIN_MAP_TEXELS, 4]), "
           "which is returned: an array kept from frame to frame is memory already mapped, where `maps` makes a new one.")
        .def_property_readonly("cluster_bounds", [](const FrameSkinning& s) {
            return to_numpy<float>(s.selection_geometry().cluster_bounds, {as_size(s.asset().cluster_count()), 4});
        }, "float32 [clusters, 4]: each L0 cluster's bounding sphere (centre, radius) at this frame, alone (what "
           "selection_geometry() holds among 3 MB more for 1000 clusters).")
        .def("selection_geometry", [](const FrameSkinning& s) {
            const LodGeometry& g = s.selection_geometry();
            const auto clusters = as_size(s.asset().cluster_count()), nc = static_cast<py::ssize_t>(s.asset().control_points);
            py::list widest, ellipsoids, thinnest;
            for (const ThickHairGeometry& level : g.levels) {
                widest.append(to_numpy<float>(level.widest, {clusters, nc, 4}));
                ellipsoids.append(to_numpy<float>(level.width_ellipsoid, {clusters, nc, 6}));
                thinnest.append(to_numpy<float>(level.thinnest, {clusters, nc}));
            }
            py::dict d;
            d["cluster_bounds"] = to_numpy<float>(g.cluster_bounds, {clusters, 4});
            d["widest"] = widest;
            d["width_ellipsoid"] = ellipsoids;
            d["thinnest"] = thinnest;
            return d;
        }, "{'cluster_bounds': [clusters, 4] spheres, 'widest': per thick level [clusters, n_c, 4] (centre, diameter), "
           "'width_ellipsoid': per thick level [clusters, n_c, 6] (xx, yy, zz, xy, yz, zx of the ellipsoid holding the "
           "hairs' semi-axes), 'thinnest': per thick level [clusters, n_c] (that ellipsoid's smallest diameter)}.");

    py::class_<ViewSelection>(m, "ViewSelection",
                              "Per-view LoD state: the initial selection, then one Huang 2025 Eq. 16 step per update, "
                              "and the index lists to draw it (vertex buffers item-major, strands in hierarchy order).")
        .def(py::init([](const LodAsset& a, const std::optional<FloatArray>& guides) {
                 if (!guides) {
                     py::gil_scoped_release release;
                     return ViewSelection(a, a.rest_geometry());
                 }
                 const std::vector<glm::vec3> points = guides_from(*guides, a);
                 py::gil_scoped_release release;
                 return ViewSelection(a, a.skin(points));
             }),
             py::arg("asset"), py::arg("guides") = py::none(), py::keep_alive<1, 2>(),
             "Selects on the asset skinned to guides [G, n_c, 3], or on its rest pose (None).")
        .def(py::init([](const FrameSkinning& s) { return ViewSelection(s.asset(), s.selection_geometry()); }),
             py::arg("skinning"), py::keep_alive<1, 2>(), "Selects on the current frame of `skinning` (no strand is skinned).")
        .def("update", [](ViewSelection& v, const FloatArray& view, const FloatArray& projection,
                          std::pair<float, float> viewport, float width_px) {
            const Camera camera{matrix_from(view, "view"), matrix_from(projection, "projection"), {viewport.first, viewport.second}};
            py::gil_scoped_release release;
            return v.update(camera, width_px);
        }, py::arg("view"), py::arg("projection"), py::arg("viewport_size"), py::arg("width_px") = kDefaultWidthPx,
           "Selects for the camera; True when the selection changed.")
        .def("reset", &ViewSelection::reset, "The next update starts from the initial selection.")
        .def("set_geometry", [](ViewSelection& v, const FrameSkinning& s) { v.set_geometry(s.selection_geometry()); },
             py::arg("skinning"), "Selects on the skinned guides of `skinning` from now on (the next update runs Huang 2025 Eq. 16).")
        .def_property_readonly("level_count", &ViewSelection::level_count)
        .def_property_readonly("level_versions", [](const ViewSelection& v) { return py::tuple(py::cast(v.level_versions())); },
                               "Per level, a count that rises whenever the segments selected at it change (an index list "
                               "from indices() built at one count stays right until it moves).")
        .def_property_readonly("selection", [](const ViewSelection& v) { return v.selection(); })
        .def("geometry", [](const ViewSelection& v, const LodAsset& a) { return geometry_dict(a, v.geometry()); },
             py::arg("asset"), "The geometry it selects on, as LodAsset.skin returns it.")
        .def("segments_per_level", [](const ViewSelection& v) {
            const std::vector<int64_t> s = v.segments_per_level();
            return to_numpy<int64_t>(s, {as_size(s.size())});
        })
        .def("strided_strand_lines", [](const ViewSelection& v, const IntArray& cluster_strides) {
            const std::vector<uint32_t> lines = v.strided_strand_lines({cluster_strides.data(), static_cast<size_t>(cluster_strides.size())});
            return to_numpy<uint32_t>(lines, {as_size(lines.size() / 2), 2});
        }, py::arg("cluster_strides"),
           "LINES indices [S, 2] of the selected strands drawn at a stride per L0 cluster (vertex LoD): the chords "
           "spanning a selected segment, each once.")
        .def("strided_strand_segments", [](const ViewSelection& v, const IntArray& cluster_strides) {
            return v.strided_strand_segments({cluster_strides.data(), static_cast<size_t>(cluster_strides.size())});
        }, py::arg("cluster_strides"), "How many chords strided_strand_lines draws.")
        .def("frame_levels", [](const ViewSelection& v) {
            std::vector<float> levels;
            std::vector<uint8_t> present;
            std::vector<int8_t> whole;
            v.frame_levels(levels, present, whole);
            const auto clusters = as_size(v.selection().visible.size());
            py::array_t<bool> present_array({clusters, static_cast<py::ssize_t>(v.level_count())});
            std::copy(present.begin(), present.end(), present_array.mutable_data());  // 0 / 1 to bool
            return py::make_tuple(to_numpy<float>(levels, {clusters, static_cast<py::ssize_t>(v.selection().segments)}),
                                  present_array, to_numpy<int8_t>(whole, {clusters}));
        }, "(levels float32 [clusters, segments], -1 where culled; present bool [clusters, level_count]; whole int8 "
           "[clusters], the level all of a visible cluster's segments are at, -1 where they differ or it is culled): "
           "the selection as a texture, which levels each visible cluster uses, and where no fragment needs the "
           "texture.")
        .def("indices", [](const ViewSelection& v, int level, const std::string& primitive) {
            DrawPrimitive kind = DrawPrimitive::lines;
            if (primitive == "strips") kind = DrawPrimitive::strips;
            else if (primitive == "segments") kind = DrawPrimitive::segments;
            else if (primitive != "lines")
                throw Error("primitive must be 'lines', 'strips' or 'segments', got '" + primitive + "'");
            const std::vector<uint32_t> indices = v.indices(level, kind);
            return to_numpy<uint32_t>(indices, {as_size(indices.size())});
        }, py::arg("level"), py::arg("primitive"),
           "Vertex indices of the selected ranges at `level`: 'lines' 2 and 'strips' 6 per segment, 'segments' "
           "one, the segment's first control point (item * n_c + segment).");

    // Cancellation is not bad input: its own exception, derived from RuntimeError.
    py::register_exception<LodBuildCancelled>(m, "BuildCancelled", PyExc_RuntimeError);
    py::class_<LodBuildProgress>(m, "LodBuildProgress", "Steps of a running build_lod, readable and cancellable from another thread.")
        .def(py::init<>())
        .def_property_readonly("done", [](const LodBuildProgress& p) { return p.done.load(); })
        .def_property_readonly("total", [](const LodBuildProgress& p) { return p.total.load(); })
        .def_property_readonly("cancelled", [](const LodBuildProgress& p) { return p.cancel.load(); })
        .def("cancel", [](LodBuildProgress& p) { p.cancel = true; }, "Stops the build at its next step (it raises BuildCancelled).");

    m.def("build_lod", [](const StrandSet& strands, int guides, int levels, int control_points, uint64_t seed,
                          float ellipse_coverage, LodBuildProgress* progress) {
        py::gil_scoped_release release;
        return build_lod(strands, {.guides = guides, .levels = levels, .control_points = control_points, .seed = seed,
                                   .ellipse_coverage = ellipse_coverage, .progress = progress});
    }, py::arg("strands"), py::arg("guides") = LodOptions{}.guides, py::arg("levels") = LodOptions{}.levels,
       py::arg("control_points") = LodOptions{}.control_points, py::arg("seed") = LodOptions{}.seed,
       py::arg("ellipse_coverage") = LodOptions{}.ellipse_coverage, py::arg("progress") = nullptr,
       "Builds an LodAsset (the GIL released); guides 0: auto_guide_count; `progress` (LodBuildProgress) reports steps and cancels.");
    m.attr("DEFAULT_VERTEX_TOLERANCE_PX") = kDefaultVertexTolerancePx;
    m.def("vertex_lod_keep", [](const FloatArray& points, const Int64Array& offsets, const FloatArray& extents,
                                const FloatArray& view, const FloatArray& projection, std::pair<float, float> viewport,
                                float tolerance_px) {
        const auto point_rows = rows_of<glm::vec3>(points, 3, "points");
        if (offsets.ndim() != 1) throw Error("offsets must be one-dimensional");
        if (extents.ndim() != 2 || extents.shape(0) != points.shape(0))
            throw Error("extents must have shape [N, k] with the points' N = " + std::to_string(points.shape(0)));
        const Camera camera{matrix_from(view, "view"), matrix_from(projection, "projection"), {viewport.first, viewport.second}};
        std::vector<uint8_t> keep;
        {
            py::gil_scoped_release release;
            keep = vertex_lod_keep({points.data(), point_rows.size() * 3}, {offsets.data(), static_cast<size_t>(offsets.size())},
                                   {extents.data(), static_cast<size_t>(extents.size())}, static_cast<int>(extents.shape(1)),
                                   camera, tolerance_px);
        }
        return to_numpy<uint8_t>(keep, {as_size(keep.size())}).attr("astype")("bool");
    }, py::arg("points"), py::arg("offsets"), py::arg("extents"), py::arg("view"), py::arg("projection"),
       py::arg("viewport_size"), py::arg("tolerance_px") = kDefaultVertexTolerancePx,
       "Vertex LoD: which control points of the curves (points [N, 3], offsets [C + 1]) to keep for this camera, "
       "points left out lying within tolerance_px pixels of the chord, extents [N, k] (world units) within it of "
       "their interpolation (lod/vertex_lod.h).");
    m.def("stride_chord_deviation", [](const FloatArray& points, int control_points, const Int64Array& item_first,
                                       const std::vector<int>& strides) {
        const auto point_rows = rows_of<glm::vec3>(points, 3, "points");
        if (item_first.ndim() != 1) throw Error("item_first must be one-dimensional");
        std::vector<float> deviation;
        {
            py::gil_scoped_release release;
            deviation = stride_chord_deviation({points.data(), point_rows.size() * 3}, control_points,
                                               {item_first.data(), static_cast<size_t>(item_first.size())}, strides);
        }
        const size_t groups = static_cast<size_t>(item_first.size()) - 1;
        return to_numpy<float>(deviation, {as_size(groups), as_size(strides.size())});
    }, py::arg("points"), py::arg("control_points"), py::arg("item_first"), py::arg("strides"),
       "Per group of items (items [item_first[g], item_first[g + 1]) of control_points points each) and stride: the "
       "largest distance of a control point from the chord drawn in its place at that stride (lod/vertex_lod.h).");
    m.def("view_block_strides", [](const FloatArray& deviation, const FloatArray& bounds, const Int64Array& block_first,
                                   const FloatArray& view, const FloatArray& projection, std::pair<float, float> viewport,
                                   float tolerance_px) {
        if (deviation.ndim() != 2 || bounds.ndim() != 2 || bounds.shape(1) != 4 || deviation.shape(0) != bounds.shape(0))
            throw Error("deviation must be [groups, strides] and bounds [groups, 4]");
        if (block_first.ndim() != 1) throw Error("block_first must be one-dimensional");
        const Camera camera{matrix_from(view, "view"), matrix_from(projection, "projection"), {viewport.first, viewport.second}};
        const std::vector<int32_t> strides = view_block_strides(
            {deviation.data(), static_cast<size_t>(deviation.size())}, static_cast<size_t>(deviation.shape(1)),
            {reinterpret_cast<const glm::vec4*>(bounds.data()), static_cast<size_t>(bounds.shape(0))},
            {block_first.data(), static_cast<size_t>(block_first.size())}, camera, tolerance_px);
        return to_numpy<int32_t>(strides, {as_size(strides.size())});
    }, py::arg("deviation"), py::arg("bounds"), py::arg("block_first"), py::arg("view"), py::arg("projection"),
       py::arg("viewport_size"), py::arg("tolerance_px"),
       "Per block of groups, the index of the longest stride whose chord deviation stays within tolerance_px pixels "
       "at every group's nearest depth (lod/vertex_lod.h).");
    m.def("level_blocks", [](const NumpyArray<bool>& present, const NumpyArray<int8_t>& whole, int level,
                             const Int64Array& block_first) {
        if (present.ndim() != 2 || whole.ndim() != 1 || present.shape(0) != whole.shape(0) || block_first.ndim() != 1)
            throw Error("level_blocks: present must be [clusters, levels], whole [clusters] and block_first one-dimensional");
        std::vector<uint8_t> draw, one_level;
        level_blocks({reinterpret_cast<const uint8_t*>(present.data()), static_cast<size_t>(present.size())},
                     static_cast<size_t>(present.shape(1)), {whole.data(), static_cast<size_t>(whole.size())}, level,
                     {block_first.data(), static_cast<size_t>(block_first.size())}, draw, one_level);
        const auto blocks = as_size(draw.size());
        return py::make_tuple(to_numpy<uint8_t>(draw, {blocks}).attr("astype")("bool"),
                              to_numpy<uint8_t>(one_level, {blocks}).attr("astype")("bool"));
    }, py::arg("present"), py::arg("whole"), py::arg("level"), py::arg("block_first"),
       "(draw, one_level) bool per block of clusters [block_first[b], block_first[b + 1]): some visible cluster has a "
       "segment at level / every cluster is visible with all its segments at it (ViewSelection.frame_levels' present "
       "and whole).");
    m.def("auto_guide_count", &auto_guide_count, py::arg("strand_count"),
          "The guide count build_lod uses when guides is 0.");
}

}  // namespace hairlod::python
