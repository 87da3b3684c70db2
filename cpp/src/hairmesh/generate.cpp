#include "hairlod/hairmesh/generate.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hairlod/core/error.h"
#include "hairlod/core/float4.h"
#include "hairlod/curves/catmull_rom.h"
#include "hairlod/hairmesh/hash_random.h"
#include "hairlod/hairmesh/level_of_detail.h"
#include "hairlod/hairmesh/tangents.h"

namespace hairlod {

namespace {

constexpr int kMaxVertexExponent = 12;
constexpr int kSampleSetCount = 4;
constexpr uint64_t kStrandLodKey = 0x6c6f64;

// A bundle's interpolated layer data at one root: control points of the strand curve and the
// styling frame and w on every layer (hair-meshes-realtime.txt Sec. 2.2 and 3.4). The frame is made
// unit on each layer (w_axis by Bhokare 2024 Eq. 4) and interpolated linearly between layers without
// renormalising, as the paper's trilinear u- and v-texture lookups do; the per-vertex square roots
// would double the cost of styling.
struct LayerSamples {
    std::vector<glm::vec3> position, u, v, w_axis;
    std::vector<float> w;
    glm::vec2 uv{0.0f};

    explicit LayerSamples(size_t layers) : position(layers), u(layers), v(layers), w_axis(layers), w(layers) {}

    // with_frames false leaves u, v and w_axis as they are (no styling operation reads them).
    void interpolate(const HairMesh& mesh, const StylingFrames& frames, const FaceCorners& corners, glm::vec2 st,
                     bool with_frames) {
        const std::array<float, 4> weight = bilinear_weights(st.x, st.y);
        uv = glm::vec2(0.0f);
        for (int k = 0; k < 4; ++k) uv += weight[k] * frames.corner_uv[corners.corner[k]];
        for (size_t layer = 0; layer < position.size(); ++layer) {
            const size_t base = layer * mesh.vertex_count;
            position[layer] = glm::vec3(0.0f);
            w[layer] = 0.0f;
            for (int k = 0; k < 4; ++k) {
                const size_t at = base + static_cast<size_t>(corners.vertex[k]);
                position[layer] += weight[k] * mesh.positions[at];
                w[layer] += weight[k] * frames.w[at];
            }
            if (!with_frames) continue;
            u[layer] = v[layer] = glm::vec3(0.0f);
            for (int k = 0; k < 4; ++k) {
                const size_t at = base + static_cast<size_t>(corners.vertex[k]);
                u[layer] += weight[k] * frames.u[at];
                v[layer] += weight[k] * frames.v[at];
            }
            u[layer] = unit_or_zero(u[layer]);
            v[layer] = unit_or_zero(v[layer]);
            w_axis[layer] = unit_or_zero(glm::cross(u[layer], v[layer]));  // Bhokare 2024 Eq. 4
        }
    }
};

// Bundle centre: the face centre (barycentric thirds for a triangle, mapped like its roots).
glm::vec2 face_centre(bool triangle) { return triangle ? triangle_to_square({1.0f / 3.0f, 1.0f / 3.0f}) : glm::vec2(0.5f); }

// Fills vertices [begin, end) of one strand, all in layer segment `segment`: the position on the
// strand's curve, uvw, and the styling inputs the operations read (styling_inputs). The frame and
// w vary linearly between layers, like the paper's u-, v- and w-textures (Sec. 3.4). Works in
// blocks of 4 vertices that may overrun `end` into the next run's slots (filled after this one) or
// the arrays' spare room (StrandVertices::kOverrun; t_of has it too): a run holds only a few
// vertices, and a scalar remainder would cost as much as the vector body.
[[gnu::noinline]] void fill_run(const LayerSamples& at_root, const CatmullRomSegment& curve,
                                const CatmullRomSegment* centre, size_t segment, const StylingInputs& inputs,
                                const float* __restrict t_of, float x_end, size_t begin, size_t end,
                                StrandVertices& vertices, glm::vec3* __restrict uvw) {
    using V = StrandVertices;
    // Explicit blocks of 4 (core/float4.h): the auto-vectoriser gives up on these short runs.
    static_assert(V::kOverrun >= 3);
    const size_t s = segment;
    const float origin = static_cast<float>(segment), w0 = at_root.w[s], w1 = at_root.w[s + 1], w_root = at_root.w[0];
    // p(a) = p1 + a (c1 + a (c2 + a c3)) per component, for the strand and the bundle centre.
    const auto cubic_into = [&](const CatmullRomSegment& segment_curve, V::Component first, Float4 a, size_t k) {
        const std::array<glm::vec3, 4> p = segment_curve.polynomial();
        for (int axis = 0; axis < 3; ++axis)
            store4(vertices[V::Component(first + axis)] + k, p[0][axis] + a * (p[1][axis] + a * (p[2][axis] + a * p[3][axis])));
    };
    const auto mix_into = [&](const std::vector<glm::vec3>& layer_values, V::Component first, Float4 a, size_t k) {
        const glm::vec3 from = layer_values[s], step = layer_values[s + 1] - layer_values[s];
        for (int axis = 0; axis < 3; ++axis) store4(vertices[V::Component(first + axis)] + k, from[axis] + step[axis] * a);
    };
    for (size_t k = begin; k < end; k += 4) {
        const Float4 t = load4(t_of + k), a = t * x_end - origin;
        cubic_into(curve, V::X, a, k);
        store4(vertices[V::W_FROM_ROOT] + k, (w0 + (w1 - w0) * a) - w_root);
        store4(vertices[V::T] + k, t);
        if (inputs.u) mix_into(at_root.u, V::UX, a, k);
        if (inputs.v) mix_into(at_root.v, V::VX, a, k);
        if (inputs.w_axis) mix_into(at_root.w_axis, V::WX, a, k);
        if (inputs.centre) cubic_into(*centre, V::CX, a, k);
    }
    const float* w_from_root = vertices[V::W_FROM_ROOT];
    for (size_t k = begin; k < end; ++k) uvw[k] = glm::vec3(at_root.uv, w_from_root[k] + w_root);
}

}  // namespace

void validate_options(const GenerateOptions& options) {
    const int segments = options.vertices - 1;
    if (segments < 1 || !std::has_single_bit(static_cast<unsigned>(segments)) ||
        std::bit_width(static_cast<unsigned>(segments)) - 1 > kMaxVertexExponent)
        throw Error("vertices must be 2^e + 1 with e in [0, " + std::to_string(kMaxVertexExponent) + "] (2, 3, 5, 9, 17, 33, ...), got " +
                    std::to_string(options.vertices));
    if (options.count > (size_t{1} << 26)) throw Error("count " + std::to_string(options.count) + " is too large");
    for (const auto& [value, name] : {std::pair{options.strand_lod, "strand LoD"}, {options.vertex_lod, "vertex LoD"},
                                      {options.lod_transition, "LoD transition"}})
        if (!(value > 0.0f && value <= 1.0f)) throw Error(std::string(name) + " must be in (0, 1], got " + std::to_string(value));
    if (!(std::isfinite(options.radius) && options.radius >= 0.0f))
        throw Error("radius must be finite and >= 0, got " + std::to_string(options.radius));
    validate_styling(options.styling);
}

std::vector<int64_t> bundle_strand_counts(const HairMesh& mesh, size_t count) {
    const size_t faces = mesh.face_count();
    std::vector<double> area(faces);
    for (size_t f = 0; f < faces; ++f) area[f] = mesh.root_face_area(f);
    const double total = std::accumulate(area.begin(), area.end(), 0.0);
    if (!(total > 0.0) || !std::isfinite(total))
        throw Error("hair mesh root layer has zero (or non-finite) area; no face can hold a strand");
    std::vector<int64_t> counts(faces);
    std::vector<double> remainder(faces);
    int64_t assigned = 0;
    for (size_t f = 0; f < faces; ++f) {
        const double exact = static_cast<double>(count) * area[f] / total;
        counts[f] = static_cast<int64_t>(std::floor(exact));
        remainder[f] = area[f] > 0.0 ? exact - static_cast<double>(counts[f]) : -1.0;
        assigned += counts[f];
    }
    std::vector<size_t> order(faces);
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return remainder[a] > remainder[b]; });
    for (size_t k = 0; assigned < static_cast<int64_t>(count); ++k, ++assigned) ++counts[order[k % faces]];
    return counts;
}

RootSampleSets root_sample_sets_for(const HairMesh& mesh, const GenerateOptions& options, const RootSampleSets* reuse) {
    const std::vector<int64_t> counts = bundle_strand_counts(mesh, options.count);
    const int64_t largest = std::max<int64_t>(1, *std::max_element(counts.begin(), counts.end()));
    bool has_quads = false, has_triangles = false;
    for (size_t f = 0; f < mesh.face_count(); ++f) (mesh.face_size(f) == 3 ? has_triangles : has_quads) = true;
    const size_t samples_per_set = std::bit_ceil(static_cast<size_t>(largest));
    if (reuse != nullptr && reuse->samples_per_set == samples_per_set && reuse->set_count == kSampleSetCount &&
        reuse->seed == options.seed && reuse->square.empty() != has_quads && reuse->triangle.empty() != has_triangles)
        return *reuse;
    return make_root_sample_sets(samples_per_set, kSampleSetCount, options.seed, has_quads, has_triangles);
}

void generate_strands(const HairMesh& mesh, const StylingFrames& frames, const RootSampleSets& samples,
                      const GenerateOptions& options, StrandSet& strands) {
    mesh.validate();
    validate_options(options);
    if (frames.u.size() != mesh.positions.size() || frames.corner_uv.size() != mesh.corner_count())
        throw Error("styling frames do not belong to this hair mesh");

    // Strand LoD (Bhokare 2024 Eq. 8) per bundle, then the strand -> (bundle, local index) table.
    const std::vector<int64_t> full_counts = bundle_strand_counts(mesh, options.count);
    const size_t faces = mesh.face_count();
    std::vector<int64_t> lod_counts(faces);
    for (size_t f = 0; f < faces; ++f)
        lod_counts[f] = lod_strand_count(full_counts[f], options.strand_lod, random_unit(options.seed, f, kStrandLodKey));
    const int64_t largest = *std::max_element(lod_counts.begin(), lod_counts.end());
    if (static_cast<size_t>(largest) > samples.samples_per_set)
        throw Error("root sample sets hold " + std::to_string(samples.samples_per_set) + " samples but a bundle needs " +
                    std::to_string(largest));
    for (size_t f = 0; f < faces; ++f)
        if (lod_counts[f] > 0 && (mesh.face_size(f) == 3 ? samples.triangle : samples.square).empty())
            throw Error("root sample sets lack the " + std::string(mesh.face_size(f) == 3 ? "triangle" : "square") +
                        " family that face " + std::to_string(f) + " needs");
    std::vector<int32_t> strand_bundle;
    std::vector<int32_t> strand_local;
    for (size_t f = 0; f < faces; ++f)
        for (int64_t j = 0; j < lod_counts[f]; ++j) {
            strand_bundle.push_back(static_cast<int32_t>(f));
            strand_local.push_back(static_cast<int32_t>(j));
        }

    // Vertex LoD (Bhokare 2024 Eq. 9, 10, 12): every strand gets 2^e + 1 vertices.
    const VertexLod lod = vertex_lod(options.vertices - 1, options.vertex_lod, options.lod_transition);
    const size_t segments = size_t{1} << lod.exponent, points_per_strand = segments + 1;
    const size_t strand_count = strand_bundle.size();

    // Reuse the output's arrays (and the attribute arrays it already holds).
    const auto take_attribute = [&strands](const char* name) {
        auto it = strands.attributes.find(name);
        return it == strands.attributes.end() ? std::vector<float>{} : std::move(it->second.values);
    };
    std::vector<float> tangent_values = take_attribute("tangent"), uvw_values = take_attribute("uvw"),
                       bundle_values = take_attribute("bundle");
    strands.attributes.clear();
    const size_t point_count = strand_count * points_per_strand;
    strands.offsets.resize(strand_count + 1);
    for (size_t c = 0; c <= strand_count; ++c) strands.offsets[c] = static_cast<int64_t>(c * points_per_strand);
    strands.points.resize(point_count);
    strands.radius.resize(point_count);
    tangent_values.resize(point_count * 3);
    uvw_values.resize(point_count * 3);
    bundle_values.resize(strand_count);

    const size_t layers = mesh.layer_count();
    const StylingInputs inputs = styling_inputs(options.styling);
    const bool with_centre = inputs.centre, styled = !options.styling.empty();
    const bool with_frames = inputs.u || inputs.v || inputs.w_axis;
    std::vector<std::vector<CatmullRomSegment>> centre_segments(with_centre ? faces : 0);
    for (size_t f = 0; f < centre_segments.size(); ++f) {
        LayerSamples centre(layers);
        const FaceCorners corners = mesh.face_corners(f);
        centre.interpolate(mesh, frames, corners, face_centre(corners.triangle), false);
        curve_segments(centre.position.data(), centre.position.size(), centre_segments[f]);
    }

    std::vector<float> t_of(points_per_strand + StrandVertices::kOverrun);  // position along the strand of vertex k
    for (size_t k = 0; k < points_per_strand; ++k) t_of[k] = static_cast<float>(k) / static_cast<float>(segments);

    tbb::parallel_for(tbb::blocked_range<size_t>(0, strand_count, 64), [&](const tbb::blocked_range<size_t>& range) {
        LayerSamples at_root(layers);
        std::vector<glm::vec3> coarse(points_per_strand);
        std::vector<CatmullRomSegment> curve;
        StrandVertices vertices;
        vertices.resize(points_per_strand);
        StrandStyling styling;
        for (size_t c = range.begin(); c != range.end(); ++c) {
            const auto bundle = static_cast<size_t>(strand_bundle[c]);
            const auto local = static_cast<size_t>(strand_local[c]);
            const FaceCorners corners = mesh.face_corners(bundle);
            at_root.interpolate(mesh, frames, corners, samples.root_coordinates(bundle, local, corners.triangle),
                               with_frames);
            curve_segments(at_root.position.data(), at_root.position.size(), curve);
            draw_strand_styling(options.styling, options.seed, (uint64_t{bundle} << 32) | local, styling);
            // Trim shortens the curve parameter range; parameter x runs over layers 0 .. layers - 1.
            const float x_end = styling.length_fraction * static_cast<float>(layers - 1);

            glm::vec3* points = strands.points.data() + c * points_per_strand;
            auto* tangents = reinterpret_cast<glm::vec3*>(tangent_values.data()) + c * points_per_strand;
            auto* uvw = reinterpret_cast<glm::vec3*>(uvw_values.data()) + c * points_per_strand;
            // Vertex k sits at curve parameter x = t_k x_end, in layer segment floor(x) (the last
            // segment takes the tip). Filled one segment's run of vertices at a time, so each inner
            // loop has fixed coefficients and vectorises.
            size_t run_begin = 0;
            for (size_t segment = 0; segment + 1 < layers; ++segment) {
                size_t end = run_begin;
                const bool last = segment + 2 == layers;
                while (end < points_per_strand && (last || t_of[end] * x_end < static_cast<float>(segment + 1))) ++end;
                fill_run(at_root, curve[segment], with_centre ? &centre_segments[bundle][segment] : nullptr, segment,
                         inputs, t_of.data(), x_end, run_begin, end, vertices, uvw);
                run_begin = end;
            }
            // Sec. 3.2: styling is not applied to the root vertex.
            if (styled) apply_styling(options.styling, styling, vertices, 1);
            for (size_t k = 0; k < points_per_strand; ++k) points[k] = vertices.vec3(StrandVertices::X, k);
            const std::span<glm::vec3> strand_points(points, points_per_strand), strand_tangents_out(tangents, points_per_strand);
            strand_tangents(vertices[StrandVertices::X], vertices[StrandVertices::Y], vertices[StrandVertices::Z],
                            strand_tangents_out);
            morph_vertex_lod(strand_points, strand_tangents_out, coarse, lod.gamma);
            const float radius = options.radius * thickness_compensation(full_counts[bundle], options.strand_lod);
            std::fill_n(strands.radius.data() + c * points_per_strand, points_per_strand, radius);
            bundle_values[c] = static_cast<float>(bundle);
        }
    });
    strands.set_attribute("tangent", AttributeDomain::Point, 3, std::move(tangent_values));
    strands.set_attribute("uvw", AttributeDomain::Point, 3, std::move(uvw_values));
    strands.set_attribute("bundle", AttributeDomain::Curve, 1, std::move(bundle_values));
}

StrandSet generate_strands(const HairMesh& mesh, const GenerateOptions& options) {
    mesh.validate();
    validate_options(options);
    StrandSet strands;
    generate_strands(mesh, compute_styling_frames(mesh), root_sample_sets_for(mesh, options), options, strands);
    return strands;
}

}  // namespace hairlod
