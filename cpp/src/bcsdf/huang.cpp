#include "hairlod/bcsdf/huang.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "hairlod/bcsdf/fiber_frame.h"

#include "hairlod/bcsdf/longitudinal.h"
#include "hairlod/bcsdf/microfacet.h"

namespace hairlod::bcsdf {

namespace {

constexpr double kPi = std::numbers::pi;
// Width-node spacing in units of the roughness: R's integrand is one microfacet lobe wide, the
// residual's smoother (Cycles' resolutions).
constexpr double kReflectionNodeSpacing = 0.7;
constexpr double kResidualNodeSpacing = 0.8;
// The visible range is shrunk by this much at both ends, where the shadowing terms are singular.
constexpr double kRangeInset = 1e-3;
// Light leaving the fibre must make at least this cosine with the internal direction (1 / eta),
// less this slack, or total internal reflection keeps it inside.
constexpr double kEscapeSlack = 1e-5;
// The Kronecker sequence of the generalised golden ratio in 4 dimensions (x^5 = x + 1): well spread
// pairs of normals, the first interface's in dimensions 0-1, the second's in 2-3, independent.
constexpr double kKronecker4[4] = {0.8566748838545029, 0.7338918566271260, 0.6287067210378086, 0.5385972572236101};

// The model's own frame (Huang et al. 2022, Fig. 5): X the major axis, Y the tangent, Z the minor axis.
glm::dvec3 to_model(const glm::dvec3& w) { return {w.y, w.x, w.z}; }
glm::dvec3 from_model(const glm::dvec3& w) { return {w.y, w.x, w.z}; }

double sin_theta(const glm::dvec3& w) { return w.y; }
double cos_theta(const glm::dvec3& w) { return std::sqrt(w.x * w.x + w.z * w.z); }
double azimuth(const glm::dvec3& w) { return std::atan2(w.x, w.z); }

// The ellipse x = sin(gamma), z = b cos(gamma): the azimuth of its outward normal at gamma, and back.
double normal_azimuth(double gamma, double b) {
    return b == 1.0 ? gamma : std::atan2(b * std::sin(gamma), std::cos(gamma));
}
double gamma_of_azimuth(double phi, double b) {
    return b == 1.0 ? phi : std::atan2(std::sin(phi), b * std::cos(phi));
}
glm::dvec2 ellipse_point(double gamma, double b) { return {std::sin(gamma), b * std::cos(gamma)}; }
// The normal at gamma tilted by theta out of the normal plane.
glm::dvec3 tilted_normal(double theta, double gamma, double b) {
    const double phi = normal_azimuth(gamma, b);
    return {std::sin(phi) * std::cos(theta), std::sin(theta), std::cos(phi) * std::cos(theta)};
}
// Arc length per unit gamma, sqrt(cos^2 + b^2 sin^2) = sqrt(1 - e^2 sin^2 gamma).
double arc_length(double e2, double gamma) {
    const double s = std::sin(gamma);
    return std::sqrt(std::max(0.0, 1.0 - e2 * s * s));
}
// The ellipse parameter where the ray along -I at offset h (divided by the projected radius) enters.
double gamma_of_offset(double h_over_r, double b, const glm::dvec3& I) {
    const double h = std::clamp(h_over_r, -1.0, 1.0);
    return b == 1.0 ? -std::asin(h) : std::atan2(I.z, -b * I.x) - std::acos(-h);
}
bool visible(const glm::dvec3& v, const glm::dvec3& m, const glm::dvec3& h) {
    return glm::dot(v, h) > 0.0 && glm::dot(v, m) > 0.0;
}
glm::dvec3 flat(const glm::dvec3& m) { return {m.x, 0.0, m.z}; }
glm::dvec3 reflect_about(const glm::dvec3& w, const glm::dvec3& h) { return 2.0 * glm::dot(w, h) * h - w; }
double frac(double x) { return x - std::floor(x); }
// G2 / G1 for light leaving along a direction at cos_mo to the mesonormal: 0 below it, where the
// microsurface masks it (as ggx_dielectric_albedo counts it, so that the energy scale restores exactly
// what this loses; Smith's Lambda alone is even in cos_mo).
double shadowing_leaving(double a2, double cos_mi, double cos_mo) {
    return cos_mo > 0.0 ? ggx_shadowing_given_visible(a2, cos_mi, cos_mo) : 0.0;
}
double mean(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

// Beyond TRT: the geometric series T R^2 T_avg A^3 / (1 - A (1 - T_avg)) with every later
// interaction's transmittance and absorption taken from the first ones (Huang et al. 2022, Sec. 5).
glm::dvec3 higher_orders(double t, double r, const glm::dvec3& a) {
    const double t_avg = std::max(1.0 - r, 1e-5);
    return t * r * r * t_avg * a * a * a / (glm::dvec3(1.0) - a * (1.0 - t_avg));
}

// Everything the width integral needs about one fibre and one view.
struct Setup {
    double b, e2, tilt, eta, alpha, a2;
    glm::dvec3 sigma;
};

// A round fibre looks the same from every azimuth: the turn about the tangent that brings the view
// to phi = 0, where the width integral's visible range is centred.
struct AzimuthTurn {
    double c, s;
    explicit AzimuthTurn(const glm::dvec3& view) : c(std::cos(azimuth(view))), s(std::sin(azimuth(view))) {}
    glm::dvec3 apply(const glm::dvec3& w) const { return {c * w.x - s * w.z, w.y, s * w.x + c * w.z}; }
    glm::dvec3 undo(const glm::dvec3& w) const { return {c * w.x + s * w.z, w.y, -s * w.x + c * w.z}; }
};

glm::dvec3 chord_absorption(const glm::dvec3& sigma, double cos_theta_path, double chord) {
    return glm::exp(-sigma * (chord / std::max(cos_theta_path, 1e-6)));
}

}  // namespace

HuangBcsdf::HuangBcsdf(const HairParams& params, int residual_samples)
    : params_((params.validate(), params)),
      lobes_(chiang_lobes(params)),
      energy_scale_(params.microfacet_roughness, params.eta),
      residual_samples_(std::max(1, residual_samples)) {
}

double HuangBcsdf::projected_radius(const glm::dvec3& w) const {
    const glm::dvec3 m = to_model(w);
    const double in_plane = m.x * m.x + m.z * m.z;
    const double e2 = 1.0 - params_.aspect_ratio * params_.aspect_ratio;
    return in_plane > 1e-14 ? std::sqrt(1.0 - e2 * m.x * m.x / in_plane) : 1.0;
}

LobeValues HuangBcsdf::eval_lobes(const glm::dvec3& wi_fibre, const glm::dvec3& wo_fibre) const {
    return eval_lobes(wi_fibre, wo_fibre, glm::dvec4(0.0));
}

LobeValues HuangBcsdf::eval_lobes(const glm::dvec3& wi_fibre, const glm::dvec3& wo_fibre, const glm::dvec4& rotation) const {
    LobeValues lobes;
    lobes.count = 4;
    if (glm::dot(wi_fibre, wi_fibre) <= 0.0 || glm::dot(wo_fibre, wo_fibre) <= 0.0) return lobes;
    const Setup s{params_.aspect_ratio, 1.0 - params_.aspect_ratio * params_.aspect_ratio, -params_.alpha,
                  params_.eta, params_.microfacet_roughness,
                  params_.microfacet_roughness * params_.microfacet_roughness, params_.huang_sigma_a};
    // Huang's I is the view (our wo), O the light (our wi).
    glm::dvec3 I = to_model(glm::normalize(wo_fibre)), O = to_model(glm::normalize(wi_fibre));
    if (s.b == 1.0) {
        const AzimuthTurn turn(I);
        I = turn.apply(I);
        O = turn.apply(O);
    }
    const double cos_i = std::max(cos_theta(I), kMinCos), cos_light = std::max(cos_theta(O), kMinCos);
    const double tan_tilt = std::tan(s.tilt);
    // No mesonormal faces the light: nothing reaches it.
    if (tan_tilt * sin_theta(O) / cos_light < -1.0) return lobes;
    const double span_cos = std::max(-tan_tilt * sin_theta(I) / cos_i, 0.0);
    if (span_cos > 1.0) return lobes;  // no mesonormal faces the view
    const double half_span = std::acos(span_cos);
    const double phi_i = s.b == 1.0 ? 0.0 : azimuth(I);
    double gamma_min = gamma_of_azimuth(phi_i - half_span, s.b), gamma_max = gamma_of_azimuth(phi_i + half_span, s.b);
    if (gamma_max < gamma_min) gamma_max += 2.0 * kPi;
    gamma_min += kRangeInset;
    gamma_max -= kRangeInset;
    const double range = gamma_max - gamma_min;
    if (!(range > 0.0)) return lobes;
    const double radius = projected_radius(wo_fibre);
    // Huang et al. 2022: the fibre's far-field scattering is the integral over its width divided by the
    // projected width (2 r cos theta of the view), S cos(theta_i) on the light's side.
    const double normalisation = 1.0 / (cos_i * 2.0 * radius * cos_light);
    const double eta = s.eta, inv_eta = 1.0 / eta;

    // R: composite Simpson over the visible normals, D G F / 4 per unit arc length.
    if (params_.weight_r > 0.0) {
        const glm::dvec3 wh = glm::normalize(I + O);
        const int intervals = 2 * static_cast<int>(std::ceil(range / (kReflectionNodeSpacing * s.alpha) * 0.5));
        const double step = range / intervals;
        double integral = 0.0;
        for (int i = 0; i <= intervals; ++i) {
            const double gamma = gamma_min + i * step;
            const glm::dvec3 wm = tilted_normal(s.tilt, gamma, s.b);
            if (!visible(I, flat(wm), wh) || !visible(O, flat(wm), wh)) continue;
            const double weight = (i == 0 || i == intervals) ? 0.5 : (i % 2 + 1);
            const double cos_mi = glm::dot(wm, I);
            integral += weight * ggx_distribution(s.a2, glm::dot(wm, wh)) *
                        ggx_shadowing(s.a2, cos_mi, glm::dot(wm, O)) * arc_length(s.e2, gamma) *
                        energy_scale_(cos_mi, false);
        }
        double cos_t = 0.0;
        const double f = fresnel_dielectric_general(glm::dot(I, wh), eta, cos_t);
        lobes.value[0] = glm::dvec3(params_.weight_r * 0.25 * f * integral * (2.0 / 3.0 * step) * normalisation);
    }

    // TT, TRT (and TRRT+ from the same paths): Simpson over the entry normal, a fixed stratified set
    // of visible normals at the first and second interfaces; the last interface is the one whose
    // half-vector sends the path to O.
    if (params_.weight_tt > 0.0 || params_.weight_trt > 0.0) {
        const int intervals = 2 * static_cast<int>(std::ceil(range / (kResidualNodeSpacing * s.alpha) * 0.5));
        const double step = range / intervals;
        const int samples = residual_samples_;
        glm::dvec3 tt(0.0), trt(0.0), trrt(0.0);
        for (int i = 0; i <= intervals; ++i) {
            const double gamma_mi = gamma_min + i * step;
            const glm::dvec3 wmi = tilted_normal(s.tilt, gamma_mi, s.b), wmi_macro = tilted_normal(0.0, gamma_mi, s.b);
            const double node_weight = ((i == 0 || i == intervals) ? 0.5 : (i % 2 + 1)) / samples;
            const double cos_mi1 = glm::dot(I, wmi);
            for (int k = 0; k < samples; ++k) {
                const double index = double(i * samples + k);
                const glm::dvec3 wh1 = sample_ggx_visible_normal(s.alpha, I, wmi, frac(0.5 + index * kKronecker4[0] + rotation.x),
                                                                 frac(0.5 + index * kKronecker4[1] + rotation.y));
                const double cos_hi1 = glm::dot(I, wh1);
                if (!(cos_hi1 > 0.0)) continue;
                double cos_t1 = 0.0;
                const double t1 = 1.0 - fresnel_dielectric_general(cos_hi1, eta, cos_t1);
                if (!(cos_t1 > 0.0)) continue;
                const double scale1 = energy_scale_(cos_mi1, false);
                const glm::dvec3 wt = refract_direction(I, wh1, cos_hi1, cos_t1, eta);
                const double phi_t = azimuth(wt);
                const double gamma_mt = 2.0 * normal_azimuth(phi_t, s.b) - gamma_mi;
                const glm::dvec3 wmt = tilted_normal(-s.tilt, gamma_mt, s.b), wmt_macro = tilted_normal(0.0, gamma_mt, s.b);
                const double cos_mo1 = glm::dot(-wt, wmi), cos_mi2 = glm::dot(-wt, wmt);
                if (!visible(I, wmi, wh1) || !visible(-wt, wmi, wh1) || !visible(I, wmi_macro, wh1) ||
                    !visible(-wt, wmi_macro, wh1))
                    continue;
                const double g1o = ggx_shadowing_given_visible(s.a2, cos_mi1, cos_mo1);
                const glm::dvec3 a_t = chord_absorption(
                    s.sigma, cos_theta(wt), glm::length(ellipse_point(gamma_mi, s.b) - ellipse_point(gamma_mt + kPi, s.b)));
                const double scale2 = energy_scale_(cos_mi2, true);

                if (params_.weight_tt > 0.0 && glm::dot(O, wt) >= inv_eta - kEscapeSlack) {
                    glm::dvec3 wh2 = -wt + inv_eta * O;
                    const double inv_norm = 1.0 / glm::length(wh2);
                    wh2 *= inv_norm;
                    const double cos_mh2 = glm::dot(wmt, wh2);
                    if (cos_mh2 >= 0.0) {
                        const double cos_hi2 = glm::dot(-wt, wh2), cos_ho2 = glm::dot(-O, wh2);
                        double cos_t2 = 0.0;
                        const double t2 = (1.0 - fresnel_dielectric_general(cos_hi2, inv_eta, cos_t2)) * scale2;
                        const double value = node_weight * t1 * scale1 * t2 * ggx_distribution(s.a2, cos_mh2) * g1o *
                                             ggx_shadowing(s.a2, cos_mi2, glm::dot(-O, wmt)) / cos_mo1 * cos_mi1 *
                                             cos_hi2 * cos_ho2 * inv_norm * inv_norm;
                        const glm::dvec3 path = value * a_t * arc_length(s.e2, gamma_mt);
                        if (std::isfinite(path.x + path.y + path.z)) tt += params_.weight_tt * path;
                    }
                }

                if (params_.weight_trt <= 0.0) continue;
                const glm::dvec3 wh2 = sample_ggx_visible_normal(s.alpha, -wt, wmt, frac(0.5 + index * kKronecker4[2] + rotation.z),
                                                                 frac(0.5 + index * kKronecker4[3] + rotation.w));
                const double cos_hi2 = glm::dot(-wt, wh2);
                if (!(cos_hi2 > 0.0)) continue;
                double cos_t2 = 0.0;
                const double r2 = fresnel_dielectric_general(cos_hi2, inv_eta, cos_t2);
                // wtr: the internally reflected path, pointing back against its travel (as -wt does).
                const glm::dvec3 wtr = reflect_about(wt, wh2);
                const glm::dvec3 beyond = node_weight * higher_orders(t1, r2, a_t);
                if (glm::dot(-wtr, O) < inv_eta - kEscapeSlack ||
                    !visible(-wt, wmt, wh2) || !visible(-wtr, wmt, wh2) ||
                    !visible(-wt, wmt_macro, wh2) || !visible(-wtr, wmt_macro, wh2)) {
                    trrt += beyond;
                    continue;
                }
                const double phi_tr = azimuth(wtr);
                const double gamma_mtr = gamma_mi - 2.0 * (normal_azimuth(phi_t, s.b) - normal_azimuth(phi_tr, s.b)) + kPi;
                const glm::dvec3 wmtr = tilted_normal(-s.tilt, gamma_mtr, s.b), wmtr_macro = tilted_normal(0.0, gamma_mtr, s.b);
                glm::dvec3 wh3 = wtr + inv_eta * O;
                const double inv_norm3 = 1.0 / glm::length(wh3);
                wh3 *= inv_norm3;
                const double cos_mh3 = glm::dot(wmtr, wh3);
                if (cos_mh3 < 0.0 || !visible(wtr, wmtr, wh3) || !visible(-O, wmtr, wh3) ||
                    !visible(wtr, wmtr_macro, wh3) || !visible(-O, wmtr_macro, wh3)) {
                    trrt += beyond;
                    continue;
                }
                const double cos_hi3 = glm::dot(wh3, wtr), cos_ho3 = glm::dot(wh3, -O), cos_mi3 = glm::dot(wmtr, wtr);
                double cos_t3 = 0.0;
                const double t3 = (1.0 - fresnel_dielectric_general(cos_hi3, inv_eta, cos_t3)) *
                                  energy_scale_(cos_mi3, true);
                const glm::dvec3 a_tr = chord_absorption(
                    s.sigma, cos_theta(wtr), glm::length(ellipse_point(gamma_mtr, s.b) - ellipse_point(gamma_mt, s.b)));
                const double cos_mo2 = glm::dot(wmt, -wtr);
                const double value = node_weight * t1 * scale1 * r2 * scale2 * t3 * ggx_distribution(s.a2, cos_mh3) * g1o *
                                     ggx_shadowing_given_visible(s.a2, cos_mi2, cos_mo2) *
                                     ggx_shadowing(s.a2, cos_mi3, glm::dot(wmtr, -O)) / (cos_mo1 * cos_mo2) * cos_mi1 *
                                     cos_mi2 * cos_hi3 * cos_ho3 * inv_norm3 * inv_norm3;
                const glm::dvec3 path = value * a_t * a_tr * arc_length(s.e2, gamma_mtr);
                if (std::isfinite(path.x + path.y + path.z)) trt += params_.weight_trt * path;
                trrt += beyond;
            }
        }
        const double simpson = 2.0 / 3.0 * step;
        // TRRT+ leaves along Chiang et al. 2016's longitudinal lobe of variance 4 x roughness with a
        // uniform azimuth 1 / (2 pi); 2 / pi is the width average of the series (Cycles' normalisation).
        const double m = deon_longitudinal(sin_theta(O), cos_theta(O), sin_theta(I), cos_theta(I), 4.0 * s.alpha);
        lobes.value[1] = tt * (inv_eta * inv_eta * simpson * normalisation);
        lobes.value[2] = trt * (inv_eta * inv_eta * simpson * normalisation);
        lobes.value[3] = trrt * (m / (2.0 * kPi) * (2.0 / kPi) * simpson * normalisation);
    }
    return lobes;
}

FibreSample HuangBcsdf::sample(const glm::dvec3& wo_fibre, const std::array<double, 11>& u) const {
    FibreSample result;
    if (glm::dot(wo_fibre, wo_fibre) <= 0.0) return result;
    const double b = params_.aspect_ratio, alpha = params_.microfacet_roughness, a2 = alpha * alpha;
    const double tilt = -params_.alpha, eta = params_.eta, inv_eta = 1.0 / eta;
    const AzimuthTurn turn(to_model(wo_fibre));
    const glm::dvec3 I = b == 1.0 ? turn.apply(to_model(glm::normalize(wo_fibre))) : to_model(glm::normalize(wo_fibre));
    const double gamma_mi = gamma_of_offset(2.0 * u[1] - 1.0, b, I);
    const glm::dvec3 wmi_macro = tilted_normal(0.0, gamma_mi, b), wmi = tilted_normal(tilt, gamma_mi, b);
    const double cos_mi1 = glm::dot(wmi, I);
    // The visibility rules of the model (Cycles' as well) discard light: where the tilted cuticle
    // faces away from the view, and paths a cuticle sends into the fibre's own (macro) surface.
    if (cos_mi1 < 0.0 || glm::dot(wmi_macro, I) < 0.0) {
        result.discarded = glm::dvec3(1.0);
        return result;
    }

    const glm::dvec3 wh1 = sample_ggx_visible_normal(alpha, I, wmi, u[2], u[3]);
    const glm::dvec3 wr = reflect_about(I, wh1);
    if (!visible(I, wmi_macro, wh1)) {
        result.discarded = glm::dvec3(1.0);
        return result;
    }
    double cos_t1 = 0.0;
    const double r1 = fresnel_dielectric_general(glm::dot(I, wh1), eta, cos_t1);
    const double scale1 = energy_scale_(cos_mi1, false);
    const double reflected = params_.weight_r * r1 * scale1 * shadowing_leaving(a2, cos_mi1, glm::dot(wmi, wr));
    const double r_energy = visible(wr, wmi_macro, wh1) ? reflected : 0.0;
    glm::dvec3 discarded(reflected - r_energy);

    glm::dvec3 tt(0.0), trt(0.0), trrt(0.0), w_tt(0.0), w_trt(0.0), w_trrt(0.0);
    if (cos_t1 > 0.0) {
        const glm::dvec3 wt = refract_direction(I, wh1, glm::dot(I, wh1), cos_t1, eta);
        const double phi_t = azimuth(wt);
        const double gamma_mt = 2.0 * normal_azimuth(phi_t, b) - gamma_mi;
        const glm::dvec3 wmt = tilted_normal(-tilt, gamma_mt, b), wmt_macro = tilted_normal(0.0, gamma_mt, b);
        const glm::dvec3 wh2 = sample_ggx_visible_normal(alpha, -wt, wmt, u[4], u[5]);
        const glm::dvec3 wtr = reflect_about(wt, wh2);
        const double cos_mi2 = glm::dot(-wt, wmt);
        const double t1 = (1.0 - r1) * scale1 * shadowing_leaving(a2, cos_mi1, glm::dot(wmi, -wt));
        if (!(cos_mi2 > 0.0 && visible(-wt, wmi_macro, wh1) && visible(-wt, wmt_macro, wh2))) discarded += t1;
        else {
            const glm::dvec3 a_t = chord_absorption(params_.huang_sigma_a, cos_theta(wt),
                                                    glm::length(ellipse_point(gamma_mi, b) - ellipse_point(gamma_mt + kPi, b)));
            double cos_t2 = 0.0;
            const double cos_hi2 = glm::dot(-wt, wh2);
            const double r2 = fresnel_dielectric_general(cos_hi2, inv_eta, cos_t2);
            const double t2 = 1.0 - r2;
            const double scale2 = energy_scale_(cos_mi2, true);
            if (cos_t2 > 0.0) {
                w_tt = refract_direction(-wt, wh2, cos_hi2, cos_t2, inv_eta);
                const glm::dvec3 leaving = params_.weight_tt * t1 * t2 * scale2 * a_t *
                                           shadowing_leaving(a2, cos_mi2, glm::dot(wmt, -w_tt));
                (visible(-w_tt, wmt_macro, wh2) ? tt : discarded) += leaving;
            }
            const double phi_tr = azimuth(wtr);
            const double gamma_mtr = gamma_mi - 2.0 * (normal_azimuth(phi_t, b) - normal_azimuth(phi_tr, b)) + kPi;
            const glm::dvec3 wmtr = tilted_normal(-tilt, gamma_mtr, b);
            const glm::dvec3 wh3 = sample_ggx_visible_normal(alpha, wtr, wmtr, u[6], u[7]);
            double cos_t3 = 0.0;
            const double cos_hi3 = glm::dot(wtr, wh3);
            const double r3 = fresnel_dielectric_general(cos_hi3, inv_eta, cos_t3);
            const double cos_mi3 = glm::dot(wmtr, wtr);
            const glm::dvec3 a_tr = chord_absorption(params_.huang_sigma_a, cos_theta(wtr),
                                                     glm::length(ellipse_point(gamma_mt, b) - ellipse_point(gamma_mtr, b)));
            const glm::dvec3 reaching_third = t1 * r2 * scale2 * a_t * a_tr * shadowing_leaving(a2, cos_mi2, glm::dot(wmt, -wtr));
            if (!(cos_mi3 > 0.0)) discarded += reaching_third;
            else {
                const glm::dvec3 tr = reaching_third * energy_scale_(cos_mi3, true);
                const double t3 = 1.0 - r3;
                if (cos_t3 > 0.0) {
                    w_trt = refract_direction(wtr, wh3, cos_hi3, cos_t3, inv_eta);
                    const glm::dvec3 leaving = params_.weight_trt * tr * t3 * shadowing_leaving(a2, cos_mi3, glm::dot(wmtr, -w_trt));
                    (visible(wtr, flat(wmtr), wh3) && visible(-w_trt, flat(wmtr), wh3) ? trt : discarded) += leaving;
                }
                // TRRT+: theta from Chiang et al. 2016's lobe of variance v = 4 roughness (inverting
                // d'Eon's cone), a uniform azimuth.
                const double v = 4.0 * alpha;
                const double xi = std::max(u[8], 1e-5);
                const double cone = 1.0 + v * std::log(xi + (1.0 - xi) * std::exp(-2.0 / v));
                const double sin_o = -cone * sin_theta(I) +
                                     std::sqrt(std::max(0.0, 1.0 - cone * cone)) * std::cos(2.0 * kPi * u[9]) * cos_theta(I);
                const double cos_o = std::sqrt(std::max(0.0, 1.0 - sin_o * sin_o));
                const double phi_o = 2.0 * kPi * u[10];
                w_trrt = {std::sin(phi_o) * cos_o, sin_o, std::cos(phi_o) * cos_o};
                const glm::dvec3 a_avg = glm::sqrt(a_t * a_tr);
                const double t_avg = std::max(0.5 * (t2 + t3), 1e-5);
                const glm::dvec3 a_res = a_avg * t_avg / (glm::dvec3(1.0) - a_avg * (1.0 - t_avg));
                trrt = tr * r3 * a_res * shadowing_leaving(a2, cos_mi3, glm::dot(wmtr, reflect_about(wtr, wh3)));
            }
        }
    }
    result.discarded = discarded;
    const double e_r = r_energy, e_tt = mean(tt), e_trt = mean(trt), e_trrt = mean(trrt);
    const double total = e_r + e_tt + e_trt + e_trrt;
    if (!(total > 0.0) || !std::isfinite(total)) return result;
    const double pick = u[0] * total;
    glm::dvec3 w;
    if (pick < e_r) {
        w = wr;
        result.weight = glm::dvec3(total);
        result.lobe = 0;
    } else if (pick < e_r + e_tt) {
        w = w_tt;
        result.weight = tt / e_tt * total;
        result.lobe = 1;
    } else if (pick < e_r + e_tt + e_trt) {
        w = w_trt;
        result.weight = trt / e_trt * total;
        result.lobe = 2;
    } else {
        w = w_trrt;
        result.weight = trrt / e_trrt * total;
        result.lobe = 3;
    }
    result.wi = from_model(b == 1.0 ? turn.undo(w) : w);
    return result;
}

}  // namespace hairlod::bcsdf
