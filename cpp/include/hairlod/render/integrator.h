#pragma once
// The integrators of the reference renderer (hair-lod-aggregated-bcsdf.txt Sec. 6):
//   PathTrace      full geometry, near-field Chiang BCSDF, BCSDF sampling + next-event estimation
//                  with MIS, up to max_bounces with Russian roulette (the reference);
//   DualScattering full geometry, single scattering with Zinke et al. 2008's dual scattering: the
//                  forward transmittance from shadow rays that count every hair they cross;
//   LodAggregated  LoD geometry path traced with the aggregated BCSDF of Sec. 4, strands of the
//                  selection with Chiang. A thick hair is shaded at the first member strand its ray
//                  meets inside (HairScene::intersect), with n from the strands the light crossed in
//                  the hair to reach it (its self-shadowing, in place of Huang 2025 Eq. 12-15's S) and B^ from
//                  the strands behind it (bcsdf::ClusterState::shaded_inside);
//   LodSingle      the same geometry and self-shadowing with the single-fibre Chiang BCSDF (with
//                  OwnHair::Scatter, paths scatter at the hair's own strands instead);
//   LodNoShadowing LodAggregated without the thick hair shadowing itself (ablation).
#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "hairlod/bcsdf/hair_params.h"
#include "hairlod/render/camera.h"
#include "hairlod/render/lights.h"
#include "hairlod/render/scene.h"

namespace hairlod::render {

enum class Method { PathTrace, DualScattering, LodAggregated, LodSingle, LodNoShadowing };

// "pt", "ds", "lod", "lod-single", "lod-no-s"; throws hairlod::Error naming an unknown name.
Method parse_method(std::string_view name);

// What a path leaving a strand inside a thick hair does with the hair's other strands.
//   Attenuate: it skips them, losing exp(-k (1 - a_f)) of its weight over the k strands it crosses
//              there on average (dual scattering's forward share): the light they scatter back is
//              dropped. Shadow rays through the own hair take the same factor.
//   Scatter:   it meets the next one at the Poisson arrival of the same count (HairScene::strand_inside)
//              and scatters there; shadow rays through the own hair take exp(-k), the chance of
//              meeting none. The hair's multiple scattering is traced, as the strands' is (LodSingle only).
enum class OwnHair { Attenuate, Scatter };

// "attenuate", "scatter"; throws hairlod::Error naming an unknown name.
OwnHair parse_own_hair(std::string_view name);

struct RenderOptions {
    Method method = Method::PathTrace;
    int spp = 16;
    int max_bounces = 70;  // scatterings after the camera ray's hit (0: direct light only)
    OwnHair own_hair = OwnHair::Attenuate;
    int roulette_start = 3;  // bounces before Russian roulette
    uint64_t seed = 0;
    int tile_size = 16;
    double backscatter_density = 0.7;  // Zinke's d_b (dual scattering)
    double forward_density = 0.7;      // Zinke's d_f (dual scattering)
    // Black hair, for any method: a camera ray that meets hair returns 0, one that misses (through
    // the gaps of thick hairs included) the environment. Under a white environment the image is
    // 1 - alpha.
    bool coverage_only = false;
};

struct RenderStats {
    double seconds = 0.0;        // tracing
    double setup_seconds = 0.0;  // BCSDF tables (dual scattering, aggregated grid)
    uint64_t rays = 0;  // Embree queries: closest hit, occlusion and counting
    double rays_per_second() const { return seconds > 0.0 ? rays / seconds : 0.0; }
};

struct Image {
    int width = 0, height = 0;
    std::vector<glm::vec3> pixels;  // linear radiance, rows from the top
};

// Called with the fraction done (0..1] on the calling thread between bands of tiles.
using Progress = std::function<void(double)>;

// Renders `scene` (committed). Throws hairlod::Error naming invalid options or parameters.
Image render(const HairScene& scene, const PinholeCamera& camera, const Lights& lights,
             const bcsdf::HairParams& params, const RenderOptions& options, RenderStats* stats = nullptr,
             const Progress& progress = {});

}  // namespace hairlod::render
