#include "hairlod/hairmesh/subdivision.h"

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "hairlod/core/error.h"

namespace hairlod {

namespace {

using namespace OpenSubdiv;

constexpr int kMaxLevel = 3;

// Vertex data of one layer as OpenSubdiv primvars (Clear / AddWithWeight), in double.
struct LayerVertex {
    glm::dvec3 position{0.0};
    double w = 0.0;
    void Clear(void* = nullptr) { *this = {}; }
    void AddWithWeight(const LayerVertex& source, float weight) {
        position += static_cast<double>(weight) * source.position;
        w += static_cast<double>(weight) * source.w;
    }
};

struct UvValue {
    glm::dvec2 uv{0.0};
    void Clear(void* = nullptr) { uv = glm::dvec2(0.0); }
    void AddWithWeight(const UvValue& source, float weight) { uv += static_cast<double>(weight) * source.uv; }
};

// Refines `values` (one per vertex or face-varying value of level 0) to the last level.
template <typename Value, typename Interpolate>
std::vector<Value> refine(const Far::TopologyRefiner& refiner, std::vector<Value> values, Interpolate interpolate) {
    for (int level = 1; level <= refiner.GetMaxLevel(); ++level) {
        std::vector<Value> next(static_cast<size_t>(interpolate.size(refiner.GetLevel(level))));
        interpolate(level, values.data(), next.data());
        values = std::move(next);
    }
    return values;
}

}  // namespace

HairMesh subdivide_hair_mesh(const HairMesh& mesh, int level) {
    mesh.validate();
    if (level < 0 || level > kMaxLevel)
        throw Error("subdivision level must be in [0, " + std::to_string(kMaxLevel) + "], got " + std::to_string(level));
    if (level == 0) return mesh;

    std::vector<int> face_sizes(mesh.face_count());
    for (size_t f = 0; f < face_sizes.size(); ++f) face_sizes[f] = static_cast<int>(mesh.face_size(f));
    const bool all_triangles = std::all_of(face_sizes.begin(), face_sizes.end(), [](int n) { return n == 3; });

    // Equal (vertex, uv) corners share one face-varying value, so uv is continuous except at seams.
    const bool has_uv = !mesh.corner_uv.empty();
    std::vector<UvValue> uv_values;
    std::vector<int> uv_indices(mesh.corner_count());
    if (has_uv) {
        std::map<std::tuple<int32_t, float, float>, int> unique;
        for (size_t k = 0; k < mesh.corner_count(); ++k) {
            const auto key = std::make_tuple(mesh.corner_vertices[k], mesh.corner_uv[k].x, mesh.corner_uv[k].y);
            const auto [it, added] = unique.emplace(key, static_cast<int>(uv_values.size()));
            if (added) uv_values.push_back({glm::dvec2(mesh.corner_uv[k])});
            uv_indices[k] = it->second;
        }
    }
    Far::TopologyDescriptor::FVarChannel uv_channel;
    uv_channel.numValues = static_cast<int>(uv_values.size());
    uv_channel.valueIndices = uv_indices.data();

    Far::TopologyDescriptor descriptor;
    descriptor.numVertices = static_cast<int>(mesh.vertex_count);
    descriptor.numFaces = static_cast<int>(face_sizes.size());
    descriptor.numVertsPerFace = face_sizes.data();
    descriptor.vertIndicesPerFace = mesh.corner_vertices.data();
    if (has_uv) {
        descriptor.numFVarChannels = 1;
        descriptor.fvarChannels = &uv_channel;
    }
    Sdc::Options sdc_options;
    sdc_options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    sdc_options.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    const std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(
        descriptor, Factory::Options(all_triangles ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, sdc_options)));
    if (!refiner) throw Error("OpenSubdiv rejected the hair mesh topology (non-manifold root layer?)");
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(level));
    const Far::PrimvarRefiner primvars(*refiner);
    const Far::TopologyLevel& last = refiner->GetLevel(level);

    struct VertexInterpolation {
        const Far::PrimvarRefiner& primvars;
        int size(const Far::TopologyLevel& l) const { return l.GetNumVertices(); }
        void operator()(int l, const LayerVertex* source, LayerVertex* target) const { primvars.Interpolate(l, source, target); }
    };
    struct UvInterpolation {
        const Far::PrimvarRefiner& primvars;
        int size(const Far::TopologyLevel& l) const { return l.GetNumFVarValues(0); }
        void operator()(int l, const UvValue* source, UvValue* target) const { primvars.InterpolateFaceVarying(l, source, target, 0); }
    };

    HairMesh refined;
    refined.vertex_count = static_cast<size_t>(last.GetNumVertices());
    refined.positions.resize(refined.vertex_count * mesh.layer_count());
    if (!mesh.w.empty()) refined.w.resize(refined.positions.size());
    for (size_t layer = 0; layer < mesh.layer_count(); ++layer) {
        std::vector<LayerVertex> base(mesh.vertex_count);
        for (size_t i = 0; i < mesh.vertex_count; ++i)
            base[i] = {glm::dvec3(mesh.position(layer, i)), mesh.w.empty() ? 0.0 : mesh.w[layer * mesh.vertex_count + i]};
        const std::vector<LayerVertex> values = refine(*refiner, std::move(base), VertexInterpolation{primvars});
        for (size_t i = 0; i < refined.vertex_count; ++i) {
            refined.positions[layer * refined.vertex_count + i] = glm::vec3(values[i].position);
            if (!mesh.w.empty()) refined.w[layer * refined.vertex_count + i] = static_cast<float>(values[i].w);
        }
    }
    const std::vector<UvValue> uv = has_uv ? refine(*refiner, std::move(uv_values), UvInterpolation{primvars}) : std::vector<UvValue>{};
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        const Far::ConstIndexArray vertices = last.GetFaceVertices(f);
        for (int k = 0; k < vertices.size(); ++k) refined.corner_vertices.push_back(vertices[k]);
        if (has_uv) {
            const Far::ConstIndexArray values = last.GetFaceFVarValues(f, 0);
            for (int k = 0; k < values.size(); ++k) refined.corner_uv.push_back(glm::vec2(uv[values[k]].uv));
        }
        refined.face_offsets.push_back(static_cast<int32_t>(refined.corner_vertices.size()));
    }
    refined.validate();
    return refined;
}

}  // namespace hairlod
