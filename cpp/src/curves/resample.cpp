#include "hairlod/curves/resample.h"

#include <algorithm>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/core/error.h"
#include "hairlod/curves/catmull_rom.h"

namespace hairlod {

namespace {

// Points closer than this fraction of the curve's polyline length to their predecessor are
// dropped: duplicates must not change the curve.
constexpr double kCoincidentFraction = 1e-6;

// Where an output sample falls on the input curve: the two input points around it (indices into
// the curve) and the parameter between them.
struct CurveParameter {
    size_t a, b;
    float u;
};

// Per-thread scratch space for one curve.
struct CurveScratch {
    std::vector<glm::vec3> kept_points;
    std::vector<size_t> kept_index;
    std::vector<float> cumulative;
    std::vector<CurveParameter> parameters;
};

void drop_coincident_points(std::span<const glm::vec3> curve, CurveScratch& scratch) {
    double length = 0.0;
    for (size_t i = 1; i < curve.size(); ++i) length += glm::distance(glm::dvec3(curve[i]), glm::dvec3(curve[i - 1]));
    const double tolerance = kCoincidentFraction * length;
    scratch.kept_points.assign(1, curve[0]);
    scratch.kept_index.assign(1, 0);
    for (size_t i = 1; i < curve.size(); ++i) {
        if (glm::distance(glm::dvec3(curve[i]), glm::dvec3(scratch.kept_points.back())) <= tolerance) continue;
        scratch.kept_points.push_back(curve[i]);
        scratch.kept_index.push_back(i);
    }
}

// Finds the K curve parameters equally spaced in arc length, measuring arc length on a fine
// polyline of each Catmull-Rom segment and inverting it piecewise linearly.
void arc_length_parameters(int subdivisions, CurveScratch& scratch) {
    const std::vector<glm::vec3>& kept = scratch.kept_points;
    std::vector<CurveParameter>& out = scratch.parameters;
    if (kept.size() < 2) {
        std::fill(out.begin(), out.end(), CurveParameter{0, 0, 0.0f});
        return;
    }
    const size_t segments = kept.size() - 1;
    const size_t fine_count = segments * static_cast<size_t>(subdivisions);
    std::vector<float>& cumulative = scratch.cumulative;
    cumulative.assign(fine_count + 1, 0.0f);
    for (size_t s = 0; s < segments; ++s) {
        const CatmullRomSegment segment = curve_segment(kept.data(), kept.size(), s);
        glm::vec3 previous = kept[s];
        for (int j = 1; j <= subdivisions; ++j) {
            const glm::vec3 p = segment.evaluate(static_cast<float>(j) / subdivisions);
            const size_t index = s * subdivisions + j;
            cumulative[index] = cumulative[index - 1] + glm::length(p - previous);
            previous = p;
        }
    }
    const float total = cumulative.back();
    const size_t k = out.size();
    size_t fine = 0;
    for (size_t i = 0; i < k; ++i) {
        size_t segment = segments - 1;
        float u = 1.0f;
        if (i + 1 < k) {
            const float target = total * static_cast<float>(i) / static_cast<float>(k - 1);
            while (fine + 1 < fine_count && cumulative[fine + 1] < target) ++fine;
            const float span = cumulative[fine + 1] - cumulative[fine];
            const float fraction =
                span > 0.0f ? std::clamp((target - cumulative[fine]) / span, 0.0f, 1.0f) : 0.0f;
            segment = fine / subdivisions;
            u = (static_cast<float>(fine % subdivisions) + fraction) / subdivisions;
        }
        out[i] = {segment, segment + 1, u};
    }
}

}  // namespace

StrandSet resample_strands(const StrandSet& strands, const ResampleOptions& options) {
    const int k = options.points_per_curve;
    if (k < 2) throw Error("resample: points_per_curve must be >= 2, got " + std::to_string(k));
    if (options.subdivisions_per_segment < 1)
        throw Error("resample: subdivisions_per_segment must be >= 1");
    strands.validate();
    strands.require_float_range("resample");

    const size_t curves = strands.curve_count();
    const size_t ku = static_cast<size_t>(k);
    StrandSet result;
    result.points.resize(curves * ku);
    result.radius.resize(curves * ku);
    result.offsets.resize(curves + 1);
    for (size_t c = 0; c <= curves; ++c) result.offsets[c] = static_cast<int64_t>(c * ku);

    std::vector<const Attribute*> point_attributes;
    std::vector<Attribute*> resampled_attributes;
    for (const auto& [name, attribute] : strands.attributes) {
        Attribute& copy = result.attributes[name];
        copy.domain = attribute.domain;
        copy.components = attribute.components;
        if (attribute.domain == AttributeDomain::Curve) {
            copy.values = attribute.values;
        } else {
            copy.values.resize(curves * ku * attribute.components);
            point_attributes.push_back(&attribute);
            resampled_attributes.push_back(&copy);
        }
    }

    tbb::parallel_for(tbb::blocked_range<size_t>(0, curves), [&](const tbb::blocked_range<size_t>& range) {
        CurveScratch scratch;
        scratch.parameters.resize(ku);
        for (size_t c = range.begin(); c != range.end(); ++c) {
            drop_coincident_points(strands.curve_points(c), scratch);
            arc_length_parameters(options.subdivisions_per_segment, scratch);
            const std::vector<glm::vec3>& kept = scratch.kept_points;
            const size_t first_in = static_cast<size_t>(strands.offsets[c]);
            const size_t first_out = c * ku;
            for (size_t i = 0; i < ku; ++i) {
                const CurveParameter& at = scratch.parameters[i];
                const size_t out = first_out + i;
                if (kept.size() < 2) {
                    result.points[out] = kept[0];
                } else {
                    result.points[out] = curve_segment(kept.data(), kept.size(), at.a).evaluate(at.u);
                }
                // Values are interpolated between the input points that bound the sample.
                const size_t a = first_in + scratch.kept_index[at.a];
                const size_t b = kept.size() < 2 ? a : first_in + scratch.kept_index[at.b];
                result.radius[out] = glm::mix(strands.radius[a], strands.radius[b], at.u);
                for (size_t n = 0; n < point_attributes.size(); ++n) {
                    const size_t width = static_cast<size_t>(point_attributes[n]->components);
                    const std::vector<float>& in = point_attributes[n]->values;
                    std::vector<float>& values = resampled_attributes[n]->values;
                    for (size_t j = 0; j < width; ++j)
                        values[out * width + j] = glm::mix(in[a * width + j], in[b * width + j], at.u);
                }
            }
        }
    });
    return result;
}

}  // namespace hairlod
