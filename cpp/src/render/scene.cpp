#include "hairlod/render/scene.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <bit>
#include <span>
#include <string>

#include <glm/geometric.hpp>

#include "hairlod/bcsdf/aggregated.h"
#include "hairlod/core/error.h"
#include "hairlod/render/random.h"

namespace hairlod::render {

namespace {

// A thick hair's cross-section at a point of its curve.
struct Section {
    glm::vec3 centre, tangent, major, minor;
    glm::vec2 radii;
    float density;
};

// A plane bounding a thick hair's segment at one end: points p with dot(p - point, normal) >= 0 are inside.
struct EndPlane {
    glm::vec3 point{0.0f}, normal{0.0f};
};

// What a ray's crossing of one thick-hair segment needs: the slab between the planes normal to
// the curve at its ends, and its mid-segment cross-section.
struct SegmentSlab {
    std::array<EndPlane, 2> ends;
    Section middle;
};

}  // namespace

// Buffers of one curve geometry. Each curve of m points is stored as m + 2 vertices (its ends
// repeated) so that the Catmull-Rom segments, which interpolate their two middle control points,
// pass through every point; segment s of a curve starts at its padded vertex s.
struct HairScene::Geometry {
    CurveKind kind = CurveKind::Strand;
    std::vector<glm::vec4> vertices;          // x y z radius, padded (+1 for Embree's 16-byte reads)
    std::vector<uint32_t> segment_first;      // first of the 4 control points of each segment (+3 padding)
    std::vector<uint32_t> segment_curve;      // curve of each segment
    std::vector<uint32_t> segment_point;      // the curve's (unpadded) point the segment starts at
    // Thick hairs only, per unpadded point / per curve.
    std::vector<glm::vec3> major_axis;
    std::vector<glm::vec2> radii;
    std::vector<float> density;
    std::vector<float> n_total;
    std::vector<int64_t> offsets;
    std::vector<SegmentSlab> slabs;  // per segment
    size_t segments() const { return segment_curve.size(); }
};

// Where a ray meets a thick hair's first member strand, and what lies behind it in the hair.
struct HairScene::FirstStrand {
    double t = 0.0;                // along the ray
    double behind_expected = 0.0;  // strands the ray would meet on average past it
    double behind_chord = 0.0;     // in-plane length of the ray in the hair past it
    double chord = 0.0;            // in-plane length of the ray in the whole hair
    uint32_t segment = 0;          // the segment whose slab holds the strand (when met)
    float u = 0.0f;                // and its curve parameter there
    bool met = false;
};

namespace {

void error_callback(void* user, RTCError code, const char* message) {
    auto* error = static_cast<std::string*>(user);
    if (error->empty()) error->assign("Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : ""));
}

// Uniform Catmull-Rom basis (Embree's) and its derivative at u in [0, 1].
template <typename T>
T catmull_rom(const T& p0, const T& p1, const T& p2, const T& p3, float u) {
    const float u2 = u * u, u3 = u2 * u;
    return 0.5f * ((-u3 + 2.0f * u2 - u) * p0 + (3.0f * u3 - 5.0f * u2 + 2.0f) * p1 +
                   (-3.0f * u3 + 4.0f * u2 + u) * p2 + (u3 - u2) * p3);
}
template <typename T>
T catmull_rom_derivative(const T& p0, const T& p1, const T& p2, const T& p3, float u) {
    const float u2 = u * u;
    return 0.5f * ((-3.0f * u2 + 4.0f * u - 1.0f) * p0 + (9.0f * u2 - 10.0f * u) * p1 +
                   (-9.0f * u2 + 8.0f * u + 1.0f) * p2 + (3.0f * u2 - 2.0f * u) * p3);
}

void append_curves(HairScene::Geometry& g, std::span<const glm::vec3> points, std::span<const int64_t> offsets,
                   const auto& radius_of) {
    const size_t curves = offsets.size() - 1;
    g.vertices.reserve(points.size() + 2 * curves + 1);
    for (size_t c = 0; c < curves; ++c) {
        const int64_t first = offsets[c], last = offsets[c + 1] - 1;
        const uint32_t base = static_cast<uint32_t>(g.vertices.size());
        g.vertices.emplace_back(points[first], radius_of(first));
        for (int64_t i = first; i <= last; ++i) g.vertices.emplace_back(points[i], radius_of(i));
        g.vertices.emplace_back(points[last], radius_of(last));
        for (int64_t s = 0; s < last - first; ++s) {
            g.segment_first.push_back(base + static_cast<uint32_t>(s));
            g.segment_curve.push_back(static_cast<uint32_t>(c));
            g.segment_point.push_back(static_cast<uint32_t>(first + s));
        }
    }
    // Embree reads shared buffers 16 bytes at a time: pad both past their last item.
    g.vertices.emplace_back(0.0f);
    g.segment_first.insert(g.segment_first.end(), 3, 0u);
}

// The accepted part of a ray through a thick hair: the interval of the ray inside the ellipse of
// `section` (centre c, unit axes a (major) and b (minor) normal to the tangent, radii r), clipped to
// the half-spaces of `ends` and to t >= 0, and its length measured in the section's plane. The
// member strands run along the tangent, so a ray crosses as many of them as its path's projection
// onto the section does (Sec. 4's n and the gaps): a ray at angle theta to the fibres travels
// 1 / sin(theta) times farther in 3D past the same strands.
struct ChordInterval {
    double t_near = 0.0, t_far = 0.0;  // along the ray, t_far > t_near when it crosses
    float chord = 0.0f;                // in-plane length, 0 if the ray misses
};

ChordInterval ellipse_interval(const glm::vec3& origin, const glm::vec3& direction, const Section& section,
                               std::span<const EndPlane> ends) {
    const glm::vec3 o = origin - section.centre, &a = section.major, &b = section.minor;
    const glm::vec2& r = section.radii;
    const double x0 = glm::dot(o, a) / r.x, dx = glm::dot(direction, a) / r.x;
    const double y0 = glm::dot(o, b) / r.y, dy = glm::dot(direction, b) / r.y;
    const double qa = dx * dx + dy * dy, qb = 2.0 * (x0 * dx + y0 * dy), qc = x0 * x0 + y0 * y0 - 1.0;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (qa <= 1e-20 || disc <= 0.0) return {};
    const double root = std::sqrt(disc);
    double s_far = (-qb + root) / (2.0 * qa), s_near = std::max(0.0, (-qb - root) / (2.0 * qa));
    for (const EndPlane& end : ends) {
        // Keep dot(origin + s direction - point, normal) >= 0.
        const double height = glm::dot(origin - end.point, end.normal), rate = glm::dot(direction, end.normal);
        if (std::abs(rate) < 1e-30) {
            if (height < 0.0) return {};
        } else if (rate > 0.0) {
            s_near = std::max(s_near, -height / rate);
        } else {
            s_far = std::min(s_far, -height / rate);
        }
    }
    if (!(s_far > s_near)) return {};
    const double in_plane = std::sqrt(glm::dot(direction, a) * glm::dot(direction, a) +
                                      glm::dot(direction, b) * glm::dot(direction, b));
    return {s_near, s_far, static_cast<float>((s_far - s_near) * in_plane)};
}

Section thick_section(const HairScene::Geometry& g, uint32_t segment, float u) {
    const glm::vec4* v = g.vertices.data() + g.segment_first[segment];
    Section s;
    s.centre = catmull_rom(glm::vec3(v[0]), glm::vec3(v[1]), glm::vec3(v[2]), glm::vec3(v[3]), u);
    s.tangent = catmull_rom_derivative(glm::vec3(v[0]), glm::vec3(v[1]), glm::vec3(v[2]), glm::vec3(v[3]), u);
    const float length = glm::length(s.tangent);
    s.tangent = length > 0.0f ? s.tangent / length : glm::vec3(1.0f, 0.0f, 0.0f);
    const uint32_t k = g.segment_point[segment];
    // The cross-section between the segment's two control points, linearly.
    const glm::vec3 axis = (1.0f - u) * g.major_axis[k] + u * g.major_axis[k + 1];
    s.minor = glm::cross(s.tangent, axis);
    const float minor_length = glm::length(s.minor);
    if (minor_length < 1e-12f) {  // axis along the tangent: any normal pair
        const glm::vec3 helper = std::abs(s.tangent.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
        s.minor = glm::normalize(glm::cross(s.tangent, helper));
    } else {
        s.minor /= minor_length;
    }
    s.major = glm::cross(s.minor, s.tangent);
    s.radii = (1.0f - u) * g.radii[k] + u * g.radii[k + 1];
    s.density = (1.0f - u) * g.density[k] + u * g.density[k + 1];
    return s;
}

void precompute_slabs(HairScene::Geometry& g) {
    g.slabs.resize(g.segments());
    for (uint32_t segment = 0; segment < g.segments(); ++segment) {
        const Section start = thick_section(g, segment, 0.0f), end = thick_section(g, segment, 1.0f);
        g.slabs[segment] = {{EndPlane{start.centre, start.tangent}, EndPlane{end.centre, -end.tangent}},
                            thick_section(g, segment, 0.5f)};
    }
}

// A ray's way through one thick hair: the in-plane chord summed over the hair's segments and the
// strands it meets there on average (Poisson mean, bcsdf::expected_hairs_met).
struct HairCrossing {
    float chord = 0.0f;
    double expected = 0.0;
};

double expected_in_slab(const HairScene::Geometry& g, uint32_t curve, const Section& middle, float chord) {
    return bcsdf::expected_hairs_met(std::clamp(static_cast<double>(middle.density), bcsdf::kMinClusterDensity, 1.0),
                                     chord, g.n_total[curve], middle.radii.x, middle.radii.y);
}

// The segments of a thick hair (first segment, count).
std::pair<uint32_t, uint32_t> hair_segments(const HairScene::Geometry& g, uint32_t curve) {
    return {static_cast<uint32_t>(g.offsets[curve] - static_cast<int64_t>(curve)),
            static_cast<uint32_t>(g.offsets[curve + 1] - g.offsets[curve] - 1)};
}

// Each segment contributes its chord through its own slab, between the planes normal to the curve
// at its two ends, with its mid-segment ellipse. Embree's round tubes reach a radius past each
// segment's ends (into the neighbours, and past the hair's ends, where there are no strands), and
// for a wide hair Embree reports only the union's outer surface, on whichever segment it lies: so
// the whole hair is crossed at once, from any of its hits, and decides once. A ray that starts
// inside the hair is crossed from its origin on.
HairCrossing cross_thick_hair(const HairScene::Geometry& g, uint32_t curve, const glm::vec3& origin, const glm::vec3& direction) {
    HairCrossing crossing;
    const auto [first, count] = hair_segments(g, curve);
    for (uint32_t segment = first; segment < first + count; ++segment) {
        const Section& middle = g.slabs[segment].middle;
        const float chord = ellipse_interval(origin, direction, middle, g.slabs[segment].ends).chord;
        if (!(chord > 0.0f)) continue;
        crossing.chord += chord;
        crossing.expected += expected_in_slab(g, curve, middle, chord);
    }
    return crossing;
}

// The Poisson process of the strands a ray meets (expected_hairs_met per unit of in-plane length,
// constant within each slab) reaches its first arrival where the expected count passed equals
// `arrival`. The slabs partition the hair, so their intervals along the ray are disjoint: they are
// walked in order of t. Past the last interval when `arrival` exceeds the hair's total.
HairScene::FirstStrand first_strand(const HairScene::Geometry& g, uint32_t curve, const glm::vec3& origin,
                         const glm::vec3& direction, double arrival) {
    struct Piece {
        double t_near, t_far, expected, chord;
        uint32_t segment;
    };
    std::array<Piece, 64> pieces;
    size_t used = 0;
    double t_last = 0.0;
    const auto [first, count] = hair_segments(g, curve);
    for (uint32_t segment = first; segment < first + count; ++segment) {
        const Section& middle = g.slabs[segment].middle;
        const ChordInterval interval = ellipse_interval(origin, direction, middle, g.slabs[segment].ends);
        if (!(interval.chord > 0.0f)) continue;
        t_last = std::max(t_last, interval.t_far);
        const Piece piece{interval.t_near, interval.t_far, expected_in_slab(g, curve, middle, interval.chord),
                          interval.chord, segment};
        if (used < pieces.size()) {
            pieces[used++] = piece;
        } else {  // a ray through more than 64 slabs of one hair: keep the nearest 64
            auto farthest = std::max_element(pieces.begin(), pieces.end(),
                                             [](const Piece& x, const Piece& y) { return x.t_near < y.t_near; });
            if (piece.t_near < farthest->t_near) *farthest = piece;
        }
    }
    std::sort(pieces.begin(), pieces.begin() + used, [](const Piece& x, const Piece& y) { return x.t_near < y.t_near; });
    HairScene::FirstStrand found;
    found.t = t_last;
    bool arrived = false;
    for (size_t k = 0; k < used; ++k) {
        const Piece& p = pieces[k];
        found.chord += p.chord;
        if (arrived) {
            found.behind_expected += p.expected;
            found.behind_chord += p.chord;
        } else if (arrival <= p.expected) {
            const double passed = p.expected > 0.0 ? arrival / p.expected : 0.0;
            found.t = p.t_near + (p.t_far - p.t_near) * passed;
            found.behind_expected = p.expected - arrival;
            found.behind_chord = p.chord * (1.0 - passed);
            found.segment = p.segment;
            // The curve parameter of the strand's place between the slab's end planes.
            const glm::vec3 at = origin + static_cast<float>(found.t) * direction;
            const auto& ends = g.slabs[p.segment].ends;
            const float from_start = glm::dot(at - ends[0].point, ends[0].normal);
            const float to_end = glm::dot(at - ends[1].point, ends[1].normal);
            found.u = from_start + to_end > 0.0f ? std::clamp(from_start / (from_start + to_end), 0.0f, 1.0f) : 0.5f;
            found.met = true;
            arrived = true;
        } else {
            arrival -= p.expected;
        }
    }
    return found;
}

// The uniform number that decides a ray's crossing of a thick hair: a hash of the ray and the hair,
// so that all of the hair's hits agree and a render stays deterministic. Another `salt` gives an
// independent number for the same crossing.
double crossing_uniform(const glm::vec3& origin, const glm::vec3& direction, unsigned geometry, uint32_t curve,
                        uint64_t salt = 0) {
    uint64_t key = mix64((uint64_t(geometry) << 32) | curve);
    if (salt != 0) key = mix64(key ^ salt);
    for (float c : {origin.x, origin.y, origin.z, direction.x, direction.y, direction.z})
        key = mix64(key ^ std::bit_cast<uint32_t>(c));
    return static_cast<double>(key >> 11) * 0x1.0p-53;
}

// Salt of the uniform that places the strand met across the ray (its offset h).
constexpr uint64_t kOffsetSalt = 0x6f66667365742068ull;

// Whether the ray meets one of the thick hair's strands on its way through (stochastic transparency:
// with probability 1 - exp(-expected), bcsdf::hair_hit_probability's). The same uniform u gives the
// first strand's place: given u < 1 - exp(-expected), -log(1 - u) is the first Poisson arrival.
bool meets_a_hair(const glm::vec3& origin, const glm::vec3& direction, unsigned geometry, uint32_t curve,
                  const HairCrossing& crossing) {
    return crossing_uniform(origin, direction, geometry, curve) < -std::expm1(-crossing.expected);
}

// What the context filter needs: the ray's origin record, the geometries and the counting state.
struct RayContext {
    embree::QueryContext context;  // first member: Embree passes its address back to the filter
    const std::vector<std::unique_ptr<HairScene::Geometry>>* geometries;
    RayOrigin from;
    bool counting = false;
    int limit = 0;
    int count = 0;
    std::array<std::pair<unsigned, uint32_t>, 64> seen{};
    // The last thick hair crossed: a wide hair reports several hits (segments, entry and exit).
    unsigned crossed_geometry = RTC_INVALID_GEOMETRY_ID;
    uint32_t crossed_curve = 0;
    HairCrossing crossing;
    // Thick hairs already found along this ray whose first strand lies farther than the query's end.
    std::array<std::pair<unsigned, uint32_t>, 8> excluded{};
    int excluded_count = 0;
};

void filter(const RTCFilterFunctionNArguments* args) {
    auto* ctx = reinterpret_cast<RayContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const unsigned geom_id = RTCHitN_geomID(args->hit, args->N, i);
        const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        const float t = RTCRayN_tfar(args->ray, args->N, i);
        const HairScene::Geometry& g = *(*ctx->geometries)[geom_id];
        const uint32_t curve = g.segment_curve[prim];
        if (geom_id == ctx->from.geometry && curve == ctx->from.curve && t < ctx->from.skip_distance) {
            args->valid[i] = 0;
            continue;
        }
        const std::pair<unsigned, uint32_t> hair{geom_id, curve};
        if (std::find(ctx->excluded.begin(), ctx->excluded.begin() + ctx->excluded_count, hair) !=
            ctx->excluded.begin() + ctx->excluded_count) {
            args->valid[i] = 0;
            continue;
        }
        if (g.kind == CurveKind::Thick) {
            const glm::vec3 origin(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                                   RTCRayN_org_z(args->ray, args->N, i));
            const glm::vec3 dir(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                                RTCRayN_dir_z(args->ray, args->N, i));
            // The cache holds one ray's crossing: packets of several rays (not traced here) recompute.
            if (args->N != 1 || ctx->crossed_geometry != geom_id || ctx->crossed_curve != curve) {
                ctx->crossing = cross_thick_hair(g, curve, origin, dir);
                ctx->crossed_geometry = geom_id;
                ctx->crossed_curve = curve;
            }
            const HairCrossing& crossing = ctx->crossing;
            if (crossing.chord <= 0.0f || !meets_a_hair(origin, dir, geom_id, curve, crossing)) {
                args->valid[i] = 0;
                continue;
            }
        }
        if (ctx->counting) {
            // Round curves may report a tube's entry and exit, and neighbouring segments overlap at
            // joints: count each curve once.
            const std::pair<unsigned, uint32_t> key{geom_id, curve};
            const auto end = ctx->seen.begin() + std::min(ctx->count, static_cast<int>(ctx->seen.size()));
            if (std::find(ctx->seen.begin(), end, key) == end) {
                if (ctx->count < static_cast<int>(ctx->seen.size())) ctx->seen[ctx->count] = key;
                ++ctx->count;
            }
            if (ctx->count < ctx->limit) args->valid[i] = 0;  // keep traversing
        }
    }
}

void init_context(RayContext& ctx, const std::vector<std::unique_ptr<HairScene::Geometry>>& geometries,
                  const RayOrigin& from) {
    embree::init_context(ctx.context);
    ctx.geometries = &geometries;
    ctx.from = from;
}

RTCRay make_ray(const glm::vec3& origin, const glm::vec3& direction, float t_max) {
    RTCRay ray{};
    ray.org_x = origin.x, ray.org_y = origin.y, ray.org_z = origin.z;
    ray.dir_x = direction.x, ray.dir_y = direction.y, ray.dir_z = direction.z;
    ray.tnear = 0.0f;
    ray.tfar = t_max;
    ray.mask = 0xffffffffu;
    return ray;
}

}  // namespace

Device::Device() {
    device_ = embree::api().rtcNewDevice(nullptr);
    if (!device_) throw Error("Embree: rtcNewDevice failed (error " + std::to_string(embree::api().rtcGetDeviceError(nullptr)) + ")");
    embree::api().rtcSetDeviceErrorFunction(device_, &error_callback, &error_);
}

Device::~Device() { embree::api().rtcReleaseDevice(device_); }

void Device::check(const char* what) {
    if (error_.empty()) return;
    std::string message = std::string(what) + ": " + error_;
    error_.clear();
    throw Error(message);
}

void ThickHairs::validate() const {
    if (offsets.empty() || offsets.front() != 0) throw Error("thick hairs: offsets must start with 0");
    for (size_t c = 0; c + 1 < offsets.size(); ++c)
        if (offsets[c + 1] - offsets[c] < 2)
            throw Error("thick hairs: hair " + std::to_string(c) + " has fewer than 2 control points");
    const size_t points = static_cast<size_t>(offsets.back());
    if (centres.size() != points || major_axis.size() != points || radii.size() != points || density.size() != points)
        throw Error("thick hairs: centres, major_axis, radii and density need " + std::to_string(points) +
                    " entries (offsets.back())");
    if (n_total.size() != offsets.size() - 1)
        throw Error("thick hairs: n_total needs one entry per hair (" + std::to_string(offsets.size() - 1) + ")");
    for (size_t i = 0; i < points; ++i) {
        const glm::vec2 r = radii[i];
        if (!(std::isfinite(centres[i].x) && std::isfinite(centres[i].y) && std::isfinite(centres[i].z)))
            throw Error("thick hairs: centre " + std::to_string(i) + " is not finite");
        if (!(r.y > 0.0f && r.x >= r.y && std::isfinite(r.x)))
            throw Error("thick hairs: radii " + std::to_string(i) + " must satisfy major >= minor > 0");
        if (!(density[i] > 0.0f && density[i] <= 1.0f))
            throw Error("thick hairs: density " + std::to_string(i) + " must be in (0, 1]");
        if (!(glm::length(major_axis[i]) > 0.5f)) throw Error("thick hairs: major_axis " + std::to_string(i) + " is not unit");
    }
    for (size_t c = 0; c < n_total.size(); ++c)
        if (!(n_total[c] >= 1.0f)) throw Error("thick hairs: n_total of hair " + std::to_string(c) + " must be >= 1");
}

HairScene::HairScene(std::shared_ptr<Device> device) : device_(std::move(device)) {
    scene_ = embree::api().rtcNewScene(device_->get());
    embree::api().rtcSetSceneFlags(scene_, embree::kQueryFilterFlag);
    embree::api().rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    device_->check("rtcNewScene");
}

HairScene::~HairScene() { embree::api().rtcReleaseScene(scene_); }

void HairScene::attach(std::unique_ptr<Geometry> g) {
    if (committed_) throw Error("HairScene: geometry added after commit()");
    if (g->segments() == 0) return;
    RTCGeometry geometry = embree::api().rtcNewGeometry(device_->get(), RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE);
    embree::api().rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, g->vertices.data(), 0,
                               sizeof(glm::vec4), g->vertices.size() - 1);
    embree::api().rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, g->segment_first.data(), 0,
                               sizeof(uint32_t), g->segments());
    embree::api().rtcCommitGeometry(geometry);
    const unsigned id = embree::api().rtcAttachGeometry(scene_, geometry);
    embree::api().rtcReleaseGeometry(geometry);
    device_->check("attaching hair curves");
    if (geometries_.size() <= id) geometries_.resize(id + 1);
    geometries_[id] = std::move(g);
}

void HairScene::add_strands(const StrandSet& strands) {
    strands.validate();
    strands.require_float_range("render");
    for (size_t i = 0; i < strands.radius.size(); ++i)
        if (!(strands.radius[i] > 0.0f))
            throw Error("strands: radius of point " + std::to_string(i) + " must be > 0 to be rendered");
    auto g = std::make_unique<Geometry>();
    append_curves(*g, strands.points, strands.offsets, [&](int64_t i) { return strands.radius[i]; });
    attach(std::move(g));
}

void HairScene::add_thick_hairs(const ThickHairs& hairs) {
    hairs.validate();
    auto g = std::make_unique<Geometry>();
    g->kind = CurveKind::Thick;
    append_curves(*g, hairs.centres, hairs.offsets, [&](int64_t i) { return hairs.radii[i].x; });
    g->major_axis = hairs.major_axis;
    for (glm::vec3& a : g->major_axis) a = glm::normalize(a);
    g->radii = hairs.radii;
    g->density = hairs.density;
    g->n_total = hairs.n_total;
    g->offsets = hairs.offsets;
    precompute_slabs(*g);
    attach(std::move(g));
}

void HairScene::commit() {
    embree::api().rtcCommitScene(scene_);
    device_->check("building the hair BVH");
    committed_ = true;
}

size_t HairScene::segment_count() const {
    return segment_count(CurveKind::Strand) + segment_count(CurveKind::Thick);
}

size_t HairScene::segment_count(CurveKind kind) const {
    size_t n = 0;
    for (const auto& g : geometries_)
        if (g && g->kind == kind) n += g->segments();
    return n;
}

bool HairScene::intersect(const glm::vec3& origin, const glm::vec3& direction, float t_max, const RayOrigin& from,
                          SurfaceHit& hit) const {
    RayContext ctx;
    init_context(ctx, geometries_, from);
    // Embree reports a thick hair where the ray enters its tube; the strand the ray meets lies deeper
    // (its first Poisson arrival), and other hairs may lie in between. So after a thick hit the ray is
    // queried again up to that strand, without that hair, until the closest is known.
    bool found = false;
    float limit = t_max;
    for (int query = 0; query <= static_cast<int>(ctx.excluded.size()); ++query) {
        RTCRayHit rh{};
        rh.ray = make_ray(origin, direction, limit);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        ctx.crossed_geometry = RTC_INVALID_GEOMETRY_ID;
        embree::intersect1(scene_, ctx.context, &filter, rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
        const Geometry& g = *geometries_[rh.hit.geomID];
        const uint32_t curve = g.segment_curve[rh.hit.primID];
        float t = rh.ray.tfar;
        FirstStrand inside;  // unused for strands
        if (g.kind == CurveKind::Thick) {
            const double u = crossing_uniform(origin, direction, rh.hit.geomID, curve);
            inside = first_strand(g, curve, origin, direction, -std::log1p(-u));
            t = std::max(t, static_cast<float>(inside.t));
        }
        if (t < limit) {
            found = true;
            limit = t;
            fill_hit(g, rh, origin, direction, t, inside, hit);
        }
        if (g.kind != CurveKind::Thick || ctx.excluded_count == static_cast<int>(ctx.excluded.size())) break;
        ctx.excluded[ctx.excluded_count++] = {rh.hit.geomID, curve};
    }
    return found;
}

void HairScene::fill_hit(const Geometry& g, const RTCRayHit& rh, const glm::vec3& origin, const glm::vec3& direction,
                         float t, const FirstStrand& inside, SurfaceHit& hit) const {
    const uint32_t prim = rh.hit.primID;
    const float u = rh.hit.u;
    const glm::vec4* v = g.vertices.data() + g.segment_first[prim];
    hit.t = t;
    hit.position = origin + hit.t * direction;
    const glm::vec3 tangent = catmull_rom_derivative(glm::vec3(v[0]), glm::vec3(v[1]), glm::vec3(v[2]), glm::vec3(v[3]), u);
    const float tangent_length = glm::length(tangent);
    hit.tangent = tangent_length > 0.0f ? tangent / tangent_length : glm::vec3(1.0f, 0.0f, 0.0f);
    glm::vec3 normal(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    const float normal_length = glm::length(normal);
    hit.normal = normal_length > 0.0f ? normal / normal_length : -glm::normalize(direction);
    hit.radius = catmull_rom(v[0].w, v[1].w, v[2].w, v[3].w, u);
    hit.kind = g.kind;
    hit.geometry = rh.hit.geomID;
    hit.curve = g.segment_curve[prim];
    if (g.kind == CurveKind::Thick) {
        const Section s = thick_section(g, prim, u);
        hit.chord = static_cast<float>(inside.chord);
        hit.n_total = g.n_total[hit.curve];
        hit.density = s.density;
        hit.radii = s.radii;
        hit.strands_behind = static_cast<float>(inside.behind_expected);
        hit.cleared_chord = static_cast<float>(std::max(0.0, inside.chord - inside.behind_chord));
        // The strand met lies at an offset h across it that is uniform in [-1, 1] (strands sit anywhere
        // across the ray), not where the ray enters the wide tube: the normal that gives the fibre frame
        // (x the tangent, z towards the viewer) that h.
        const glm::vec3 towards_viewer = -direction - glm::dot(-direction, hit.tangent) * hit.tangent;
        const float across = glm::length(towards_viewer);
        if (across > 1e-6f) {
            const glm::vec3 z = towards_viewer / across, y = glm::cross(z, hit.tangent);
            const float h = static_cast<float>(2.0 * crossing_uniform(origin, direction, hit.geometry, hit.curve,
                                                                      kOffsetSalt) - 1.0);
            hit.normal = h * y + std::sqrt(std::max(0.0f, 1.0f - h * h)) * z;
        }
    }
}

bool HairScene::strand_inside(const SurfaceHit& hit, const glm::vec3& direction, double arrival, SurfaceHit& next) const {
    if (hit.kind != CurveKind::Thick) return false;
    const Geometry& g = *geometries_[hit.geometry];
    const FirstStrand inside = first_strand(g, hit.curve, hit.position, direction, arrival);
    if (!inside.met) return false;
    RTCRayHit rh{};
    rh.hit.geomID = hit.geometry;
    rh.hit.primID = inside.segment;
    rh.hit.u = inside.u;
    rh.hit.Ng_x = -direction.x, rh.hit.Ng_y = -direction.y, rh.hit.Ng_z = -direction.z;
    fill_hit(g, rh, hit.position, direction, static_cast<float>(inside.t), inside, next);
    return true;
}

HairPassage HairScene::own_hair_passage(const SurfaceHit& hit, const glm::vec3& direction) const {
    if (hit.kind != CurveKind::Thick) return {};
    const HairCrossing crossing = cross_thick_hair(*geometries_[hit.geometry], hit.curve, hit.position, direction);
    return {crossing.chord, crossing.expected};
}

bool HairScene::occluded(const glm::vec3& origin, const glm::vec3& direction, float t_max, const RayOrigin& from) const {
    RayContext ctx;
    init_context(ctx, geometries_, from);
    RTCRay ray = make_ray(origin, direction, t_max);
    embree::occluded1(scene_, ctx.context, &filter, ray);
    return ray.tfar < 0.0f;
}

int HairScene::count_crossings(const glm::vec3& origin, const glm::vec3& direction, float t_max, const RayOrigin& from,
                               int limit) const {
    RayContext ctx;
    init_context(ctx, geometries_, from);
    ctx.counting = true;
    ctx.limit = std::max(1, limit);
    RTCRay ray = make_ray(origin, direction, t_max);
    embree::occluded1(scene_, ctx.context, &filter, ray);
    return std::min(ctx.count, ctx.limit);
}

RayOrigin HairScene::leaving(const SurfaceHit& hit, const glm::vec3& direction) const {
    // A ray leaving the tube may cross it again (transmission) over at most the chord of a tube of
    // radius r at its inclination: 2 r / sin(angle to the tangent), with margin; capped for rays
    // along the fibre.
    const float along = std::abs(glm::dot(direction, hit.tangent));
    const float across = std::sqrt(std::max(0.0f, 1.0f - along * along));
    const float r = hit.kind == CurveKind::Thick ? hit.radii.x : hit.radius;
    return RayOrigin{hit.geometry, hit.curve, 3.0f * r / std::max(across, 0.1f)};
}

}  // namespace hairlod::render
