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
// unit on each layer (w_axis by Eq. 4) and interpolated linearly between layers without
// renormalising, as the paper's trilinear u- and v-texture lookups do; the per-vertex square roots
// would double the cost of styling.
struct LayerSamples {
    std::vector<glm::vec3> position, u, v, w_axis;
    std::vector<float> w;
    glm::vec2 uv{0.0f};

    explicit LayerSamples(size_t layers) : position(layers), u(layers), v(layers), w_axis(layers), w(layers) {}

    void interpolate(const HairMesh& mesh, const StylingFrames& frames, const FaceCorners& corners, glm::vec2 st) {
        const std::array<float, 4> weight = bilinear_weights(st.x, st.y);
        uv = glm::vec2(0.0f);
        for (int k = 0; k < 4; ++k) uv += weight[k] * frames.corner_uv[corners.corner[k]];
        for (size_t layer = 0; layer < position.size(); ++layer) {
            const size_t base = layer * mesh.vertex_count;
            position[layer] = u[layer] = v[layer] = glm::vec3(0.0f);
            w[layer] = 0.0f;
            for (int k = 0; k < 4; ++k) {
                const size_t at = base + static_cast<size_t>(corners.vertex[k]);
                position[layer] += weight[k] * mesh.positions[at];
                u[layer] += weight[k] * frames.u[at];
                v[layer] += weight[k] * frames.v[at];
                w[layer] += weight[k] * frames.w[at];
            }
            u[layer] = unit_or_zero(u[layer]);
            v[layer] = unit_or_zero(v[layer]);
            w_axis[layer] = unit_or_zero(glm::cross(u[layer], v[layer]));  // Eq. 4
        }
    }
};

void curve_segments(const std::vector<glm::vec3>& control, std::vector<CatmullRomSegment>& segments) {
    segments.clear();
    for (size_t i = 0; i + 1 < control.size(); ++i) segments.push_back(curve_segment(control.data(), control.size(), i));
}

bool needs_centre(const std::vector<StylingOperation>& styling) {
    return std::any_of(styling.begin(), styling.end(), [](const StylingOperation& op) {
        return std::holds_alternative<Clump>(op) || std::holds_alternative<Twist>(op);
    });
}

// Bundle centre: the face centre (barycentric thirds for a triangle, mapped like its roots).
glm::vec2 face_centre(bool triangle) { return triangle ? triangle_to_square({1.0f / 3.0f, 1.0f / 3.0f}) : glm::vec2(0.5f); }

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

RootSampleSets root_sample_sets_for(const HairMesh& mesh, const GenerateOptions& options) {
    const std::vector<int64_t> counts = bundle_strand_counts(mesh, options.count);
    const int64_t largest = std::max<int64_t>(1, *std::max_element(counts.begin(), counts.end()));
    bool has_quads = false, has_triangles = false;
    for (size_t f = 0; f < mesh.face_count(); ++f) (mesh.face_size(f) == 3 ? has_triangles : has_quads) = true;
    return make_root_sample_sets(std::bit_ceil(static_cast<size_t>(largest)), kSampleSetCount, options.seed,
                                 has_quads, has_triangles);
}

void generate_strands(const HairMesh& mesh, const StylingFrames& frames, const RootSampleSets& samples,
                      const GenerateOptions& options, StrandSet& strands) {
    mesh.validate();
    validate_options(options);
    if (frames.u.size() != mesh.positions.size() || frames.corner_uv.size() != mesh.corner_count())
        throw Error("styling frames do not belong to this hair mesh");

    // Strand LoD (Eq. 8) per bundle, then the strand -> (bundle, local index) table.
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

    // Vertex LoD (Eq. 9, 10, 12): every strand gets 2^e + 1 vertices.
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
    const bool with_centre = needs_centre(options.styling), styled = !options.styling.empty();
    std::vector<std::vector<CatmullRomSegment>> centre_segments(with_centre ? faces : 0);
    for (size_t f = 0; f < centre_segments.size(); ++f) {
        LayerSamples centre(layers);
        const FaceCorners corners = mesh.face_corners(f);
        centre.interpolate(mesh, frames, corners, face_centre(corners.triangle));
        curve_segments(centre.position, centre_segments[f]);
    }

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
            at_root.interpolate(mesh, frames, corners, samples.root_coordinates(bundle, local, corners.triangle));
            curve_segments(at_root.position, curve);
            draw_strand_styling(options.styling, options.seed, (uint64_t{bundle} << 32) | local, styling);
            // Trim shortens the curve parameter range; parameter x runs over layers 0 .. layers - 1.
            const float x_end = styling.length_fraction * static_cast<float>(layers - 1);

            glm::vec3* points = strands.points.data() + c * points_per_strand;
            auto* tangents = reinterpret_cast<glm::vec3*>(tangent_values.data()) + c * points_per_strand;
            auto* uvw = reinterpret_cast<glm::vec3*>(uvw_values.data()) + c * points_per_strand;
            using V = StrandVertices;
            for (size_t k = 0; k < points_per_strand; ++k) {
                const float t = static_cast<float>(k) / static_cast<float>(segments);
                const float x = t * x_end;
                const size_t segment = std::min(static_cast<size_t>(x), layers - 2);
                const float a = x - static_cast<float>(segment);
                // The frame and w vary linearly between layers, like the paper's u-, v- and w-textures.
                const float w = glm::mix(at_root.w[segment], at_root.w[segment + 1], a);
                uvw[k] = glm::vec3(at_root.uv, w);
                const glm::vec3 position = curve[segment].evaluate(a);
                vertices.set_vec3(V::X, k, position);
                if (styled) {
                    vertices.set_vec3(V::UX, k, glm::mix(at_root.u[segment], at_root.u[segment + 1], a));
                    vertices.set_vec3(V::VX, k, glm::mix(at_root.v[segment], at_root.v[segment + 1], a));
                    vertices.set_vec3(V::WX, k, glm::mix(at_root.w_axis[segment], at_root.w_axis[segment + 1], a));
                    vertices.set_vec3(V::CX, k, with_centre ? centre_segments[bundle][segment].evaluate(a) : position);
                    vertices[V::W_FROM_ROOT][k] = w - at_root.w[0];
                    vertices[V::T][k] = t;
                }
            }
            // Sec. 3.2: styling is not applied to the root vertex.
            if (styled) apply_styling(options.styling, styling, vertices, 1);
            for (size_t k = 0; k < points_per_strand; ++k) points[k] = vertices.vec3(V::X, k);
            const std::span<glm::vec3> strand_points(points, points_per_strand), strand_tangents_out(tangents, points_per_strand);
            strand_tangents(strand_points, strand_tangents_out);
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
