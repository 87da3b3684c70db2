#include "hairlod/render/integrator.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hairlod/bcsdf/aggregated.h"
#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/fiber_frame.h"
#include "hairlod/bcsdf/fiber_rtd.h"
#include "hairlod/bcsdf/huang.h"
#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/core/error.h"
#include "hairlod/render/chiang_sampling.h"
#include "hairlod/render/random.h"

namespace hairlod::render {

namespace {

using namespace hairlod::bcsdf;
constexpr double kPi = std::numbers::pi;
constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Probability of the far-field Chiang proposal when sampling the aggregated BCSDF; the rest is uniform over the
// sphere, which keeps the mixture density positive wherever the aggregated lobes are.
constexpr double kAggregatedChiangFraction = 0.7;
constexpr double kUniformSpherePdf = 1.0 / (4.0 * kPi);
// Visible normals per width node of the Huang fibre's TT / TRT quadrature in the path tracer, at a
// random rotation per shading point: unbiased, and the noise averages out over the pixel's samples
// (Cycles also draws one).
constexpr int kPathTracedHuangNormals = 1;
// Passes of one ray beside elliptical fibres (through their round tubes) before the path is ended: a
// ray grazing along a strand meets its tube segment after segment, and two tubes through the same
// point can hand the ray to each other without it moving on (a pixel of the wavy test hair never ended).
constexpr int kMaxPassesBeside = 256;

// The fibre frame at a hit seen from wo: x = tangent, z = wo's component normal to the fibre, y =
// z x x (pbrt's curve frame), and the offset h in [-1, 1] of the hit across the fibre along y.
struct Frame {
    glm::dvec3 x, y, z;
    glm::dvec3 local(const glm::dvec3& w) const { return {glm::dot(w, x), glm::dot(w, y), glm::dot(w, z)}; }
    glm::dvec3 world(const glm::dvec3& w) const { return w.x * x + w.y * y + w.z * z; }
};

glm::dvec3 any_normal(const glm::dvec3& t) {
    const glm::dvec3 helper = std::abs(t.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    return glm::normalize(glm::cross(t, helper));
}

Frame fibre_frame(const SurfaceHit& hit, const glm::dvec3& wo, double& h) {
    Frame f;
    f.x = glm::dvec3(hit.tangent);
    const glm::dvec3 across = wo - glm::dot(wo, f.x) * f.x;
    f.z = glm::length(across) > 1e-9 ? glm::normalize(across) : any_normal(f.x);
    f.y = glm::cross(f.z, f.x);
    // The tube's outward normal on the side the ray came from.
    glm::dvec3 n = glm::dvec3(hit.normal);
    n -= glm::dot(n, f.x) * f.x;
    if (glm::dot(n, f.z) < 0.0) n = -n;
    h = glm::length(n) > 1e-12 ? std::clamp(glm::dot(glm::normalize(n), f.y), -1.0, 1.0) : 0.0;
    return f;
}

glm::dvec3 uniform_sphere(double u1, double u2) {
    const double z = 1.0 - 2.0 * u1;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(2.0 * kPi * u2), r * std::sin(2.0 * kPi * u2), z};
}

// The major axis of an elliptical fibre at a hit: Cycles' Huang closure without a normal attribute on
// the curves takes the second vector of its fixed orthonormal basis around the tangent t (the first is
// (1, 1, 1) x t normalised, or (-1, 1, 1) x t where t's components are all equal); the same here, so
// that both renderers orient the ellipse alike.
glm::dvec3 major_axis(const glm::dvec3& t) {
    glm::dvec3 a = (t.x != t.y || t.x != t.z) ? glm::dvec3(t.z - t.y, t.x - t.z, t.y - t.x)
                                             : glm::dvec3(t.z - t.y, t.x + t.z, -t.y - t.x);
    a = glm::normalize(a);
    return glm::cross(t, a);
}

double channel_max(const glm::dvec3& v) { return std::max({v.x, v.y, v.z}); }
double channel_mean(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

double power_heuristic(double a, double b) {
    const double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

// One shading point: its frame, wo in it, and which BCSDF applies there.
struct Vertex {
    Frame frame;
    glm::dvec3 wo{0.0};
    double h = 0.0;
    bool aggregated = false;
    double hair_count = 1.0;
    // A thick hair that shadows its own hit (lod, lod-single; not lod-no-s): light reaches the hit
    // through the hair's other strands (HairScene::own_hair_passage), which rays leaving the hit skip.
    bool self_shadowed = false;
    // Huang fibre: the frame turned about the tangent so that +y is the ellipse's major axis
    // (cos, sin of the turn), and whether the ray passed beside the ellipse inside the round tube.
    double ellipse_cos = 1.0, ellipse_sin = 0.0;
    bool beside_fibre = false;
    glm::dvec4 normal_rotation{0.0};  // of the Huang fibre's visible normals at this point
    glm::dvec3 to_ellipse(const glm::dvec3& w) const {
        return {w.x, ellipse_cos * w.y + ellipse_sin * w.z, -ellipse_sin * w.y + ellipse_cos * w.z};
    }
    glm::dvec3 from_ellipse(const glm::dvec3& w) const {
        return {w.x, ellipse_cos * w.y - ellipse_sin * w.z, ellipse_sin * w.y + ellipse_cos * w.z};
    }
};

class Shader {
public:
    Shader(const HairParams& params, const RenderOptions& options) : chiang_(params), method_(options.method) {
        const bool lod_aggregated = method_ == Method::LodAggregated || method_ == Method::LodNoShadowing;
        if (lod_aggregated || method_ == Method::DualScattering || method_ == Method::LodSingle) {
            const FiberRtdBcsdf fiber(params);
            table_ = std::make_shared<const AggregatedTable>(aggregated_table(fiber, 33, options.backscatter_density));
        }
        if (lod_aggregated) aggregated_ = std::make_unique<AggregatedBcsdf>(params, ClusterState{}, table_);
        if (method_ == Method::DualScattering) fiber_ = std::make_unique<FiberRtdBcsdf>(params);
        // Strands are shaded with the material's fibre; dual scattering and the aggregated model use the
        // Chiang fibre (for a Huang material, the one fitted to it: HairParams::beta_m, beta_n).
        if (params.fibre == FibreModel::Huang) huang_ = std::make_unique<HuangBcsdf>(params, kPathTracedHuangNormals);
        scatter_inside_ = options.own_hair == OwnHair::Scatter;
    }
    // Whether paths scatter at the strands of their own thick hair (OwnHair::Scatter).
    bool scatters_inside() const { return scatter_inside_; }

    Vertex vertex(const SurfaceHit& hit, const glm::dvec3& wo_world, Random& rng) const {
        Vertex v;
        v.frame = fibre_frame(hit, wo_world, v.h);
        v.wo = v.frame.local(wo_world);
        v.self_shadowed = hit.kind == CurveKind::Thick && method_ != Method::LodNoShadowing;
        if (huang_ && !(hit.kind == CurveKind::Thick && aggregated_)) {
            if (huang_->params().aspect_ratio != 1.0) {
                const glm::dvec3 major = major_axis(v.frame.x);
                const double turn = std::atan2(glm::dot(major, v.frame.z), glm::dot(major, v.frame.y));
                v.ellipse_cos = std::cos(turn);
                v.ellipse_sin = std::sin(turn);
            }
            // Cycles' Huang closure: a hit on the round tube outside the ellipse's projected half-width
            // is transparent.
            v.beside_fibre = std::abs(v.h) >= huang_->projected_radius(v.to_ellipse(v.wo));
            v.normal_rotation = {rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()};
        }
        if (hit.kind == CurveKind::Thick && aggregated_) {
            v.aggregated = true;
            // The first strand the ray met inside the hair, and the strands behind it (Huang 2025 Eq. 10's A_1+).
            v.hair_count = 1.0 + hit.strands_behind;
        }
        return v;
    }

    // The strands of the hit's own thick hair that light arriving along wi_world crossed on its way to
    // the hit (Poisson mean; 0 unless the hit shadows itself). Rays leaving the hit skip its own hair,
    // so this is the hair shadowing itself. The strands are not independent of the view: the camera ray
    // found no strand centre within a strand radius r of its path before the hit (hit.cleared_chord
    // long, in the cross-section's plane), and the light's path shares that empty corridor near the
    // hit. Two strips of width 2 r from one point at an in-plane angle phi overlap over an area of
    // (2 r)^2 / (2 sin phi), so the light meets mu r / sin(phi) fewer strands (mu: strands met per
    // unit in-plane length), at most the part of its path inside the corridor; none when it arrives
    // from beyond the hit (cos phi <= 0). This is the shadowing that Huang 2025 Eq. 12-15 of
    // hair-lod-aggregated-bcsdf.txt estimate for a renderer shading the hair's surface (S grows with
    // phi and falls with rho), so S is 1 here (rho = 1 in Huang 2025 Eq. 15: open fraction 0).
    // `passage`, when given, receives the way out before that correction.
    double light_crossings(const Vertex& v, const HairScene& scene, const SurfaceHit& hit, const glm::dvec3& wi_world,
                           HairPassage* passage_out = nullptr) const {
        if (!v.self_shadowed) return 0.0;
        const HairPassage passage = scene.own_hair_passage(hit, glm::vec3(wi_world));
        if (passage_out != nullptr) *passage_out = passage;
        double expected = passage.expected;
        if (!(expected > 0.0)) return 0.0;
        const glm::dvec3 wi = v.frame.local(wi_world);
        const double in_plane_i = std::hypot(wi.y, wi.z), in_plane_o = std::hypot(v.wo.y, v.wo.z);
        if (in_plane_i > 1e-9 && in_plane_o > 1e-9) {
            const double cos_phi = (wi.y * v.wo.y + wi.z * v.wo.z) / (in_plane_i * in_plane_o);
            if (cos_phi > 0.0) {
                const double density = std::clamp(static_cast<double>(hit.density), kMinClusterDensity, 1.0);
                const double per_length = expected_hairs_met(density, 1.0, hit.n_total, hit.radii.x, hit.radii.y);
                const double strand_radius = std::sqrt(density * hit.radii.x * hit.radii.y / hit.n_total);
                const double sin_phi = std::sqrt(std::max(0.0, 1.0 - cos_phi * cos_phi));
                const double shared = std::min({strand_radius / std::max(sin_phi, 1e-9), double(passage.chord),
                                                double(hit.cleared_chord)});
                expected = std::max(0.0, expected - per_length * shared);
            }
        }
        return expected;
    }

    // S(wi, wo) cos(theta_i), wi in the vertex frame; `crossings` from light_crossings.
    glm::dvec3 eval(const Vertex& v, const glm::dvec3& wi, double crossings = 0.0) const {
        const double cos_i = std::sqrt(std::max(0.0, 1.0 - wi.x * wi.x));
        // The model at this hit's n and rho directly: one evaluation, no table of models to interpolate.
        if (v.aggregated)
            return aggregated_->eval_lobes(wi, v.wo, {v.hair_count, 1.0, true, crossings}).sum() * cos_i;
        const glm::dvec3 fibre = huang_ ? huang_->eval_lobes(v.to_ellipse(wi), v.to_ellipse(v.wo), v.normal_rotation).sum()
                                        : chiang_.eval_lobes(wi, v.wo, v.h).sum();
        return fibre * std::max(cos_i, kMinCos) * shadowing(wi, crossings);
    }

    // The single fibre behind `crossings` strands that each pass on a_f forwards (dual scattering,
    // Zinke et al. 2008): E[a_f^k] = exp(-k (1 - a_f)) for a Poisson count k. When paths scatter at
    // those strands, what they pass on forwards is traced: the light arrives unscattered, P(0) = exp(-k).
    glm::dvec3 shadowing(const glm::dvec3& wi, double crossings) const {
        if (!(crossings > 0.0)) return glm::dvec3(1.0);
        if (scatter_inside_) return glm::dvec3(std::exp(-crossings));
        const glm::dvec3 a_f = table_->sample(fiber_direction(wi).theta).a_f;
        return glm::exp(-crossings * (1.0 - glm::min(a_f, glm::dvec3(1.0))));
    }

    // The Huang fibre has no closed-form density; as in Cycles, its samples carry their weight and its
    // density reads 1 for both sampling strategies, which keeps the MIS weights summing to 1.
    double pdf(const Vertex& v, const glm::dvec3& wi) const {
        if (!v.aggregated && huang_) return 1.0;
        if (!v.aggregated) return chiang_pdf(chiang_, wi, v.wo, v.h);
        return kAggregatedChiangFraction * chiang_far_field_pdf(chiang_, wi, v.wo) +
               (1.0 - kAggregatedChiangFraction) * kUniformSpherePdf;
    }

    // A direction wi (vertex frame) with its pdf; `crossings(wi)` gives light_crossings for the value.
    template <typename Crossings>
    BcsdfSample sample(const Vertex& v, Random& rng, const Crossings& crossings) const {
        const std::array<double, 4> u{rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()};
        if (!v.aggregated && huang_) {
            std::array<double, 11> draw;
            for (double& d : draw) d = rng.uniform();
            const FibreSample f = huang_->sample(v.to_ellipse(v.wo), draw);
            BcsdfSample s;
            if (!(glm::dot(f.wi, f.wi) > 0.0)) return s;
            s.wi = v.from_ellipse(f.wi);
            s.pdf = 1.0;
            s.value = f.weight * (v.self_shadowed ? shadowing(s.wi, crossings(s.wi)) : glm::dvec3(1.0));
            return s;
        }
        if (!v.aggregated) {
            BcsdfSample s = sample_chiang(chiang_, v.wo, v.h, u);
            if (v.self_shadowed && s.pdf > 0.0) s.value = eval(v, s.wi, crossings(s.wi));
            return s;
        }
        BcsdfSample s;
        if (rng.uniform() < kAggregatedChiangFraction)
            s.wi = sample_chiang_far_field(chiang_, v.wo, {u[0], u[1], u[2], u[3], rng.uniform()}).wi;
        else s.wi = uniform_sphere(u[0], u[1]);
        s.pdf = pdf(v, s.wi);
        s.value = eval(v, s.wi, crossings(s.wi));
        return s;
    }

    // Dual scattering (Zinke et al. 2008; Xu et al. 2011, Sec. 4.3) for light crossing `crossed`
    // hairs before reaching the shading point, S cos(theta_i):
    //   n = 0: f_s (near-field Chiang) + d_b f_back;
    //   n > 0: d_f a_f^n (f_s broadened by n forward scatterings + d_b f_back broadened),
    // with the broadening of hair-lod-aggregated-bcsdf.txt Eq. 7 and 9 (variances add per crossing:
    // longitudinal 4 n beta_f^2 in theta_i, azimuthal n sigma_f^2) applied to the R, TT, D fibre,
    // and f_back = A_b G(theta_i; 2 Delta_b - theta_o, 4 sigma_b^2 + 4 n beta_f^2) / pi over the
    // backward half (|phi| < pi/2), the normalisation of the aggregated B^ lobe.
    glm::dvec3 dual_scattering(const Vertex& v, const glm::dvec3& wi, int crossed, const RenderOptions& options) const {
        const FiberDirection di = fiber_direction(wi), dout = fiber_direction(v.wo);
        const HalfAngles angles = half_angles(di, dout);
        const DualScatteringSample hair = table_->sample(angles.theta_d);
        const double beta_f2 = channel_mean(hair.beta_f * hair.beta_f);
        const double n = crossed;
        glm::dvec3 back(0.0);
        if (std::abs(angles.phi) < 0.5 * kPi) {
            for (int c = 0; c < 3; ++c) {
                const double variance = std::max(4.0 * hair.sigma_b[c] * hair.sigma_b[c] + 4.0 * n * beta_f2, 1e-12);
                back[c] = hair.A_b[c] * gaussian_longitudinal(di.theta, dout.theta, hair.delta_b[c], variance) / kPi;
            }
        }
        const double cos_i = std::max(di.cos_theta, kMinCos);
        if (crossed == 0) return (chiang_.eval_lobes(wi, v.wo, v.h).sum() + options.backscatter_density * back) * cos_i;
        RtdSpread spread;
        spread.longitudinal_variance = 4.0 * n * beta_f2;
        spread.azimuthal_variance = n * channel_mean(table_->azimuthal_variance(angles.theta_d));
        const glm::dvec3 transmittance = options.forward_density * glm::pow(hair.a_f, glm::dvec3(n));
        return transmittance * (fiber_->eval_lobes(wi, v.wo, spread).sum() + options.backscatter_density * back) * cos_i;
    }

private:
    ChiangBcsdf chiang_;
    std::unique_ptr<HuangBcsdf> huang_;
    Method method_;
    std::shared_ptr<const AggregatedTable> table_;
    std::unique_ptr<AggregatedBcsdf> aggregated_;
    std::unique_ptr<FiberRtdBcsdf> fiber_;
    bool scatter_inside_ = false;
};

struct Tracer {
    const HairScene& scene;
    const PinholeCamera& camera;
    const Lights& lights;
    const RenderOptions& options;
    const Shader& shader;
    bool environment_lit;

    // Direct light at v (next-event estimation) with MIS against BCSDF sampling for the
    // environment; delta lights by their shadow ray alone. `rays` counts Embree queries.
    glm::dvec3 direct(const Vertex& v, const SurfaceHit& hit, Random& rng, uint64_t& rays) const {
        glm::dvec3 sum(0.0);
        const glm::vec3 p = hit.position;
        for (const DirectionalLight& light : lights.directional) {
            const glm::vec3 wi = -glm::normalize(light.direction);
            const glm::dvec3 f = shader.eval(v, v.frame.local(glm::dvec3(wi)), shader.light_crossings(v, scene, hit, wi));
            if (channel_max(f) <= 0.0) continue;
            ++rays;
            if (!scene.occluded(p, wi, kInfinity, scene.leaving(hit, wi))) sum += f * glm::dvec3(light.irradiance);
        }
        for (const PointLight& light : lights.points) {
            const glm::vec3 to_light = light.position - p;
            const float distance = glm::length(to_light);
            if (!(distance > 0.0f)) continue;
            const glm::vec3 wi = to_light / distance;
            const glm::dvec3 f = shader.eval(v, v.frame.local(glm::dvec3(wi)), shader.light_crossings(v, scene, hit, wi));
            if (channel_max(f) <= 0.0) continue;
            ++rays;
            if (!scene.occluded(p, wi, distance * (1.0f - 1e-5f), scene.leaving(hit, wi)))
                sum += f * glm::dvec3(light.intensity) / double(distance * distance);
        }
        if (environment_lit) {
            // The environment drawn by its luminance (uniformly when constant), MIS against the BCSDF.
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const EnvironmentSample light = lights.environment.sample(u1, u2);
            const glm::dvec3 wi_world = glm::normalize(glm::dvec3(light.towards));
            const glm::dvec3 wi = v.frame.local(wi_world);
            const glm::dvec3 f = light.pdf > 0.0 ? shader.eval(v, wi, shader.light_crossings(v, scene, hit, wi_world))
                                                 : glm::dvec3(0.0);
            if (channel_max(f) > 0.0) {
                const glm::vec3 w(wi_world);
                ++rays;
                if (!scene.occluded(p, w, kInfinity, scene.leaving(hit, w))) {
                    const double weight = power_heuristic(light.pdf, shader.pdf(v, wi));
                    sum += f * glm::dvec3(lights.environment.radiance(w)) * (weight / light.pdf);
                }
            }
        }
        return sum;
    }

    glm::dvec3 path(glm::vec3 origin, glm::vec3 direction, Random& rng, uint64_t& rays) const {
        glm::dvec3 radiance(0.0), throughput(1.0);
        RayOrigin from;
        double previous_pdf = 0.0;  // of the BCSDF sample that made this ray; 0 for the camera ray
        int passes_beside = 0;
        // OwnHair::Scatter: the strand of the previous hit's own thick hair that this ray meets, if any;
        // anything closer along the ray comes first.
        SurfaceHit own_strand;
        bool meets_own_strand = false;
        // Past max_bounces the path still takes one BCSDF sample: next-event estimation weighted the
        // environment's light by MIS against it, so without it an environment-lit hit would keep only
        // the light sample's share (an isolated strand read 0.16 of its light under a white sky at
        // max_bounces 0, 0.66 at 1). That ray adds the environment if it escapes, nothing if it hits.
        bool escape_only = false;
        for (int bounce = 0;; ++bounce) {
            SurfaceHit hit;
            ++rays;
            bool found = scene.intersect(origin, direction, meets_own_strand ? own_strand.t : kInfinity, from, hit);
            if (!found && meets_own_strand) {
                hit = own_strand;
                found = true;
            }
            meets_own_strand = false;
            if (!found) {
                const glm::dvec3 env(lights.environment.radiance(direction));
                const double weight = bounce == 0 ? 1.0 : power_heuristic(previous_pdf, lights.environment.pdf(direction));
                radiance += throughput * env * (environment_lit ? weight : 1.0);
                break;
            }
            if (options.coverage_only) break;
            const glm::dvec3 wo = -glm::dvec3(direction);
            const Vertex v = shader.vertex(hit, wo, rng);
            if (v.beside_fibre) {
                // Through the round tube beside the elliptical fibre, as if it were not there.
                if (++passes_beside > kMaxPassesBeside) break;
                origin = hit.position;
                from = scene.leaving(hit, direction);
                --bounce;
                continue;
            }
            if (escape_only) break;
            radiance += throughput * direct(v, hit, rng, rays);
            if (bounce >= options.max_bounces) {
                if (!environment_lit) break;
                escape_only = true;
            }
            const BcsdfSample s = shader.sample(v, rng, [&](const glm::dvec3& wi) {
                // Scattering inside, the path meets the own hair's strands itself (below).
                return shader.scatters_inside() ? 0.0 : shader.light_crossings(v, scene, hit, v.frame.world(wi));
            });
            if (!(s.pdf > 0.0) || channel_max(s.value) <= 0.0) break;
            throughput *= s.value / s.pdf;
            previous_pdf = s.pdf;
            direction = glm::vec3(glm::normalize(v.frame.world(s.wi)));
            origin = hit.position;
            from = scene.leaving(hit, direction);
            if (shader.scatters_inside() && v.self_shadowed) {
                // The strands ahead in the own hair, less those the camera's empty corridor rules out
                // (light_crossings): a Poisson count, whose first arrival is where the ray meets one.
                // The corridor lies next to the hit, so the arrival is counted past its share.
                HairPassage way_out;
                const double open = shader.light_crossings(v, scene, hit, glm::dvec3(direction), &way_out);
                const double total = way_out.expected;
                const double u = rng.uniform();
                if (u < -std::expm1(-open))
                    meets_own_strand = scene.strand_inside(hit, direction, -std::log1p(-u) + (total - open), own_strand);
            }
            if (bounce + 1 >= options.roulette_start) {
                const double survive = std::min(0.95, channel_max(throughput));
                if (!(rng.uniform() < survive)) break;
                throughput /= survive;
            }
        }
        return radiance;
    }

    // Camera hit + every light through dual scattering; no further bounces (the multiple scattering
    // is the dual-scattering approximation's).
    glm::dvec3 dual(glm::vec3 origin, glm::vec3 direction, Random& rng, uint64_t& rays) const {
        SurfaceHit hit;
        ++rays;
        if (!scene.intersect(origin, direction, kInfinity, {}, hit))
            return glm::dvec3(lights.environment.radiance(direction));
        const Vertex v = shader.vertex(hit, -glm::dvec3(direction), rng);
        const glm::vec3 p = hit.position;
        glm::dvec3 sum(0.0);
        auto gather = [&](const glm::vec3& wi, float distance, const glm::dvec3& radiance) {
            ++rays;
            const int crossed = scene.count_crossings(p, wi, distance, scene.leaving(hit, wi));
            sum += shader.dual_scattering(v, v.frame.local(glm::dvec3(wi)), crossed, options) * radiance;
        };
        for (const DirectionalLight& light : lights.directional)
            gather(-glm::normalize(light.direction), kInfinity, glm::dvec3(light.irradiance));
        for (const PointLight& light : lights.points) {
            const glm::vec3 to_light = light.position - p;
            const float distance = glm::length(to_light);
            if (distance > 0.0f)
                gather(to_light / distance, distance * (1.0f - 1e-5f), glm::dvec3(light.intensity) / double(distance * distance));
        }
        if (environment_lit) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const EnvironmentSample light = lights.environment.sample(u1, u2);
            if (light.pdf > 0.0)
                gather(glm::normalize(light.towards), kInfinity, glm::dvec3(lights.environment.radiance(light.towards)) / light.pdf);
        }
        return sum;
    }
};

}  // namespace

Method parse_method(std::string_view name) {
    if (name == "pt") return Method::PathTrace;
    if (name == "ds") return Method::DualScattering;
    if (name == "lod") return Method::LodAggregated;
    if (name == "lod-single") return Method::LodSingle;
    if (name == "lod-no-s") return Method::LodNoShadowing;
    throw Error("unknown render method '" + std::string(name) + "' (expected pt, ds, lod, lod-single or lod-no-s)");
}

OwnHair parse_own_hair(std::string_view name) {
    if (name == "attenuate") return OwnHair::Attenuate;
    if (name == "scatter") return OwnHair::Scatter;
    throw Error("unknown own-hair treatment '" + std::string(name) + "' (expected attenuate or scatter)");
}

Image render(const HairScene& scene, const PinholeCamera& camera, const Lights& lights, const HairParams& params,
             const RenderOptions& options, RenderStats* stats, const Progress& progress) {
    if (options.spp < 1) throw Error("spp must be >= 1, got " + std::to_string(options.spp));
    if (options.max_bounces < 0) throw Error("max_bounces must be >= 0, got " + std::to_string(options.max_bounces));
    if (options.own_hair == OwnHair::Scatter && options.method != Method::LodSingle)
        throw Error("own_hair 'scatter' applies to the lod-single method only");
    if (options.tile_size < 1) throw Error("tile_size must be >= 1, got " + std::to_string(options.tile_size));
    if (!(options.backscatter_density >= 0.0 && options.forward_density >= 0.0))
        throw Error("backscatter and forward densities must be >= 0");
    lights.validate();
    params.validate();
    auto start = std::chrono::steady_clock::now();
    const Shader shader(params, options);
    const double setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    start = std::chrono::steady_clock::now();
    const Tracer tracer{scene, camera, lights, options, shader, !lights.environment.black()};

    Image image;
    image.width = camera.width();
    image.height = camera.height();
    image.pixels.assign(static_cast<size_t>(image.width) * image.height, glm::vec3(0.0f));
    const int tiles_x = (image.width + options.tile_size - 1) / options.tile_size;
    const int tiles_y = (image.height + options.tile_size - 1) / options.tile_size;
    std::atomic<uint64_t> rays{0};
    // One band of tile rows at a time, so that progress is reported from this thread.
    for (int band = 0; band < tiles_y; ++band) {
        tbb::parallel_for(0, tiles_x, [&](int tx) {
            uint64_t tile_rays = 0;
            const int x0 = tx * options.tile_size, y0 = band * options.tile_size;
            for (int y = y0; y < std::min(y0 + options.tile_size, image.height); ++y)
                for (int x = x0; x < std::min(x0 + options.tile_size, image.width); ++x) {
                    const uint64_t pixel = static_cast<uint64_t>(y) * image.width + x;
                    glm::dvec3 sum(0.0);
                    for (int s = 0; s < options.spp; ++s) {
                        Random rng(options.seed, pixel, static_cast<uint64_t>(s));
                        const CameraRay ray = camera.ray(x + rng.uniform(), y + rng.uniform());
                        // Coverage is the geometry's alone: the path tracer stops at the camera ray's hit.
                        const glm::dvec3 value = options.method == Method::DualScattering && !options.coverage_only
                                                     ? tracer.dual(ray.origin, ray.direction, rng, tile_rays)
                                                     : tracer.path(ray.origin, ray.direction, rng, tile_rays);
                        // A NaN from any single path would poison the pixel: drop it (counted as black).
                        if (std::isfinite(value.x + value.y + value.z)) sum += value;
                    }
                    image.pixels[pixel] = glm::vec3(sum / double(options.spp));
                }
            rays += tile_rays;
        });
        if (progress) progress(double(band + 1) / tiles_y);
    }
    if (stats) {
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        stats->rays = rays.load();
        stats->setup_seconds = setup_seconds;
    }
    return image;
}

}  // namespace hairlod::render
