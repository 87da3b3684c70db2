// Hair meshes: HairMesh, the styling operations, and strand generation (GIL released).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <optional>
#include <string>

#include "bindings.h"
#include "numpy_arrays.h"
#include "hairlod/core/error.h"
#include "hairlod/hairmesh/generate.h"
#include "hairlod/hairmesh/level_of_detail.h"
#include "hairlod/hairmesh/subdivision.h"

namespace py = pybind11;

namespace hairlod::python {

namespace {


HairMesh make_mesh(const FloatArray& layers, const IntArray& polygon_sizes, const IntArray& polygon_vertices,
                   const std::optional<FloatArray>& uv, const std::optional<FloatArray>& w) {
    if (layers.ndim() != 3 || layers.shape(2) != 3)
        throw Error("layers must have shape [layers, vertices, 3]");
    if (polygon_sizes.ndim() != 1 || polygon_vertices.ndim() != 1)
        throw Error("polygon sizes and polygon vertices must be one-dimensional");
    const auto layer_count = static_cast<size_t>(layers.shape(0)), vertex_count = static_cast<size_t>(layers.shape(1));
    std::vector<glm::vec3> positions(layer_count * vertex_count);
    std::memcpy(positions.data(), layers.data(), positions.size() * sizeof(glm::vec3));
    std::vector<glm::vec2> corner_uv;
    if (uv) {
        if (uv->ndim() != 2 || uv->shape(1) != 2) throw Error("uv must have shape [corners, 2]");
        corner_uv.resize(static_cast<size_t>(uv->shape(0)));
        std::memcpy(corner_uv.data(), uv->data(), corner_uv.size() * sizeof(glm::vec2));
    }
    std::vector<float> w_values;
    if (w) {
        if (w->ndim() != 2 || w->shape(0) != layers.shape(0) || w->shape(1) != layers.shape(1))
            throw Error("w must have shape [layers, vertices] like the layers");
        w_values.assign(w->data(), w->data() + w->size());
    }
    return make_hair_mesh(std::move(positions), vertex_count,
                          {polygon_sizes.data(), static_cast<size_t>(polygon_sizes.size())},
                          {polygon_vertices.data(), static_cast<size_t>(polygon_vertices.size())}, corner_uv,
                          std::move(w_values));
}

// Frames and root sample sets depend only on the mesh, the strand count and the seed: a generator
// keeps them, so regenerating with other styling or LoD (interactive editing) skips that work.
class StrandGenerator {
public:
    // `reuse`: a generator for an earlier state of the mesh, whose root sample sets are taken when
    // they are the ones this mesh needs (an edit rebuilds only the frames).
    StrandGenerator(HairMesh mesh, size_t count, uint64_t seed, const StrandGenerator* reuse) : mesh_(std::move(mesh)) {
        options_.count = count;
        options_.seed = seed;
        frames_ = compute_styling_frames(mesh_);
        samples_ = root_sample_sets_for(mesh_, options_, reuse != nullptr ? &reuse->samples_ : nullptr);
    }

    // Writes into `strands`, reusing its storage.
    void generate(int vertices, std::vector<StylingOperation> styling, float strand_lod, float vertex_lod,
                  float lod_transition, float radius, StrandSet& strands) const {
        GenerateOptions options = options_;
        options.vertices = vertices;
        options.styling = std::move(styling);
        options.strand_lod = strand_lod;
        options.vertex_lod = vertex_lod;
        options.lod_transition = lod_transition;
        options.radius = radius;
        generate_strands(mesh_, frames_, samples_, options, strands);
    }

    const HairMesh& mesh() const { return mesh_; }
    size_t count() const { return options_.count; }
    uint64_t seed() const { return options_.seed; }

private:
    HairMesh mesh_;
    GenerateOptions options_;
    StylingFrames frames_;
    RootSampleSets samples_;
};

// "Name(key=value, ...)" with values printed like Python's %g.
std::string operation_repr(const char* name, std::initializer_list<std::pair<const char*, float>> parameters) {
    std::string text = std::string(name) + "(";
    for (const auto& [key, value] : parameters) {
        if (text.back() != '(') text += ", ";
        text += std::string(key) + "=" + py::str(py::float_(value).attr("__format__")("g")).cast<std::string>();
    }
    return text + ")";
}

}  // namespace

void bind_hairmesh(py::module_& m) {
    py::class_<HairMesh>(m, "HairMesh", R"doc(
A hair mesh: root-layer polygons extruded into layers that share their topology
(hair-meshes-realtime.txt Sec. 2.2). Polygons with more than 4 vertices are split into quads and
a triangle. Construct from layers float32 [L, V, 3] (L >= 2, layer 0 the root layer), polygon sizes
int32 [P], polygon vertex indices int32 [sum of sizes], optional uv float32 [sum of sizes, 2] per
polygon corner and optional w float32 [L, V]; validated (ValueError naming the problem).)doc")
        .def(py::init(&make_mesh), py::arg("layers"), py::arg("polygon_sizes"), py::arg("polygon_vertices"),
             py::arg("uv") = py::none(), py::arg("w") = py::none())
        .def_property_readonly("layer_count", &HairMesh::layer_count)
        .def_property_readonly("vertex_count", [](const HairMesh& h) { return h.vertex_count; })
        .def_property_readonly("face_count", &HairMesh::face_count)
        .def_property_readonly("layers",
                               [](const HairMesh& h) {
                                   return to_numpy(point_floats(h.positions).data(),
                                                     {static_cast<py::ssize_t>(h.layer_count()),
                                                      static_cast<py::ssize_t>(h.vertex_count), 3});
                               },
                               "A copy of the positions, float32 [L, V, 3].")
        .def_property_readonly("face_sizes",
                               [](const HairMesh& h) {
                                   std::vector<int32_t> sizes(h.face_count());
                                   for (size_t f = 0; f < sizes.size(); ++f) sizes[f] = static_cast<int32_t>(h.face_size(f));
                                   return to_numpy(sizes.data(), {static_cast<py::ssize_t>(sizes.size())});
                               },
                               "Vertices of each face after splitting (3 or 4), int32 [F].")
        .def_property_readonly("face_vertices",
                               [](const HairMesh& h) {
                                   return to_numpy(h.corner_vertices.data(),
                                                     {static_cast<py::ssize_t>(h.corner_vertices.size())});
                               })
        .def_property_readonly("uv",
                               [](const HairMesh& h) -> py::object {
                                   if (h.corner_uv.empty()) return py::none();
                                   return to_numpy(reinterpret_cast<const float*>(h.corner_uv.data()), {static_cast<py::ssize_t>(h.corner_uv.size()), 2});
                               })
        .def_property_readonly("w",
                               [](const HairMesh& h) -> py::object {
                                   if (h.w.empty()) return py::none();
                                   return to_numpy(h.w.data(), {static_cast<py::ssize_t>(h.layer_count()),
                                                                  static_cast<py::ssize_t>(h.vertex_count)});
                               })
        .def("root_face_areas",
             [](const HairMesh& h) {
                 std::vector<double> areas(h.face_count());
                 for (size_t f = 0; f < areas.size(); ++f) areas[f] = h.root_face_area(f);
                 return to_numpy(areas.data(), {static_cast<py::ssize_t>(areas.size())});
             })
        .def("subdivided",
             [](const HairMesh& h, int level) {
                 py::gil_scoped_release release;
                 return subdivide_hair_mesh(h, level);
             },
             py::arg("level"),
             "OpenSubdiv refinement (Catmull-Clark, or Loop for all-triangle meshes) of every layer, level 0-3.")
        .def("__repr__", [](const HairMesh& h) {
            return "HairMesh(layers=" + std::to_string(h.layer_count()) + ", vertices=" + std::to_string(h.vertex_count) +
                   ", faces=" + std::to_string(h.face_count()) + ")";
        });

    py::class_<Curl>(m, "Curl", "Helix around the strand: radius (object units), frequency (turns per unit w), randomness [0, 1].")
        .def(py::init([](float radius, float frequency, float randomness) { return Curl{radius, frequency, randomness}; }),
             py::kw_only(), py::arg("radius") = 0.0f, py::arg("frequency") = 0.0f, py::arg("randomness") = 0.0f)
        .def_readwrite("radius", &Curl::radius)
        .def_readwrite("frequency", &Curl::frequency)
        .def_readwrite("randomness", &Curl::randomness)
        .def("__repr__", [](const Curl& o) { return operation_repr("Curl", {{"radius", o.radius}, {"frequency", o.frequency}, {"randomness", o.randomness}}); });
    py::class_<Wave>(m, "Wave", "Planar wave along u: amplitude (object units), frequency (periods per unit w), randomness [0, 1].")
        .def(py::init([](float amplitude, float frequency, float randomness) { return Wave{amplitude, frequency, randomness}; }),
             py::kw_only(), py::arg("amplitude") = 0.0f, py::arg("frequency") = 0.0f, py::arg("randomness") = 0.0f)
        .def_readwrite("amplitude", &Wave::amplitude)
        .def_readwrite("frequency", &Wave::frequency)
        .def_readwrite("randomness", &Wave::randomness)
        .def("__repr__", [](const Wave& o) { return operation_repr("Wave", {{"amplitude", o.amplitude}, {"frequency", o.frequency}, {"randomness", o.randomness}}); });
    py::class_<Twist>(m, "Twist", "Rotation about the bundle's centre curve: rate (turns per unit w).")
        .def(py::init([](float rate) { return Twist{rate}; }), py::kw_only(), py::arg("rate") = 0.0f)
        .def_readwrite("rate", &Twist::rate)
        .def("__repr__", [](const Twist& o) { return operation_repr("Twist", {{"rate", o.rate}}); });
    py::class_<Clump>(m, "Clump", "Pull towards the bundle's centre curve: amount [0, 1] at the tip, profile exponent > 0.")
        .def(py::init([](float amount, float profile) { return Clump{amount, profile}; }), py::kw_only(),
             py::arg("amount") = 0.0f, py::arg("profile") = 1.0f)
        .def_readwrite("amount", &Clump::amount)
        .def_readwrite("profile", &Clump::profile)
        .def("__repr__", [](const Clump& o) { return operation_repr("Clump", {{"amount", o.amount}, {"profile", o.profile}}); });
    py::class_<Frizz>(m, "Frizz", "Smooth per-strand noise: amplitude (object units), frequency (cells per unit w).")
        .def(py::init([](float amplitude, float frequency) { return Frizz{amplitude, frequency}; }), py::kw_only(),
             py::arg("amplitude") = 0.0f, py::arg("frequency") = 0.0f)
        .def_readwrite("amplitude", &Frizz::amplitude)
        .def_readwrite("frequency", &Frizz::frequency)
        .def("__repr__", [](const Frizz& o) { return operation_repr("Frizz", {{"amplitude", o.amplitude}, {"frequency", o.frequency}}); });
    py::class_<Trim>(m, "Trim", "Length randomisation: each strand keeps a random fraction in [1 - amount, 1].")
        .def(py::init([](float amount) { return Trim{amount}; }), py::kw_only(), py::arg("amount") = 0.0f)
        .def_readwrite("amount", &Trim::amount)
        .def("__repr__", [](const Trim& o) { return operation_repr("Trim", {{"amount", o.amount}}); });

    py::class_<StrandGenerator>(m, "StrandGenerator", R"doc(
Generates strands from a hair mesh. Keeps the styling frames and the blue-noise root sample sets
(which depend on the mesh, count and seed only), so regenerating with other styling or LoD is fast.)doc")
        .def(py::init([](const HairMesh& mesh, size_t count, uint64_t seed, const StrandGenerator* reuse) {
                 py::gil_scoped_release release;
                 return StrandGenerator(mesh, count, seed, reuse);
             }),
             py::arg("mesh"), py::arg("count"), py::arg("seed") = 0, py::arg("reuse") = nullptr,
             "reuse: a generator made for an earlier state of the mesh; its root sample sets are taken when they "
             "are exactly the ones this one needs (same count, seed and sample set size), as after vertex edits.")
        .def("generate",
             [](const StrandGenerator& g, int vertices, std::vector<StylingOperation> styling, float strand_lod,
                float vertex_lod, float lod_transition, float radius, py::object out) {
                 if (out.is_none()) out = py::cast(StrandSet{});
                 auto& strands = out.cast<StrandSet&>();
                 {
                     py::gil_scoped_release release;
                     g.generate(vertices, std::move(styling), strand_lod, vertex_lod, lod_transition, radius, strands);
                 }
                 return out;
             },
             py::kw_only(), py::arg("vertices") = 17, py::arg("styling") = std::vector<StylingOperation>{},
             py::arg("strand_lod") = 1.0f, py::arg("vertex_lod") = 1.0f, py::arg("lod_transition") = 0.5f,
             py::arg("radius") = 0.0f, py::arg("out") = py::none(),
             R"doc(Strands with point attributes 'tangent' [N, 3], 'uvw' [N, 3] and curve attribute 'bundle'.

out: Strands to overwrite and return, reusing their memory (repeated generation of the same size
then allocates nothing). Arrays read from `out` before the call must not be used after it.)doc")
        .def_property_readonly("mesh", &StrandGenerator::mesh)
        .def_property_readonly("count", &StrandGenerator::count)
        .def_property_readonly("seed", &StrandGenerator::seed);

    m.def("detail_level", &detail_level, py::arg("model_size"), py::arg("resolution_px"), py::arg("distance"),
          py::arg("field_of_view"), py::arg("alpha") = 1.0f,
          "hair-meshes-realtime.txt Eq. 7: L = min(1, alpha h R / (d tan(theta))).");
}

}  // namespace hairlod::python
