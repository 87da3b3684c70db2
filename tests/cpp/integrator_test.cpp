#include "hairlod/render/integrator.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "hairlod/core/error.h"
#include "hairlod/render/random.h"

namespace hairlod::render {
namespace {

// A loose tuft: `count` wavy strands along x through y in [-0.6, 0.6], z in [-0.2, 0.2].
StrandSet tuft(int count, float radius) {
    StrandSet s;
    Random rng(11, 0, 0);
    for (int c = 0; c < count; ++c) {
        const float y = float(rng.uniform() * 1.2 - 0.6), z = float(rng.uniform() * 0.4 - 0.2);
        const float phase = float(rng.uniform() * 6.28);
        std::vector<glm::vec3> pts;
        for (int k = 0; k < 8; ++k) {
            const float x = -1.0f + 2.0f * k / 7.0f;
            pts.emplace_back(x, y + 0.05f * std::sin(3.0f * x + phase), z + 0.05f * std::cos(2.0f * x + phase));
        }
        s.add_curve(pts, std::vector<float>(pts.size(), radius));
    }
    return s;
}

ThickHairs thick_tuft() {
    ThickHairs hairs;
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 6; ++k) {
            hairs.centres.emplace_back(-1.0f + 0.4f * k, -0.4f + 0.4f * c, 0.0f);
            hairs.major_axis.emplace_back(0.0f, 1.0f, 0.0f);
            hairs.radii.emplace_back(0.12f, 0.05f);
            hairs.density.push_back(0.4f);
        }
        hairs.offsets.push_back(hairs.offsets.back() + 6);
        hairs.n_total.push_back(60.0f);
    }
    return hairs;
}

const PinholeCamera kCamera({0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.6f, 24, 24);

struct Rendered {
    Image image;
    RenderStats stats;
};

Rendered render_with(const HairScene& scene, const Lights& lights, const bcsdf::HairParams& params, Method method,
                     int spp, uint64_t seed = 1) {
    RenderOptions options;
    options.method = method;
    options.spp = spp;
    options.seed = seed;
    Rendered r;
    r.image = render(scene, kCamera, lights, params, options, &r.stats);
    return r;
}

// The tuft path-traced at 16 spp in a uniform white environment (radiance 1), no other light.
Rendered tuft_in_white(const bcsdf::HairParams& params) {
    HairScene scene(std::make_shared<Device>());
    scene.add_strands(tuft(60, 0.02f));
    scene.commit();
    Lights lights;
    lights.environment = Environment(glm::vec3(1.0f));
    return render_with(scene, lights, params, Method::PathTrace, 16);
}

double mean_radiance(const Image& image) {
    double sum = 0.0;
    for (const glm::vec3& p : image.pixels) sum += p.x + p.y + p.z;
    return sum / (3.0 * image.pixels.size());
}

// White furnace: a lossless fibre (sigma_a = 0) in a uniform environment of radiance 1 returns
// radiance 1 at every pixel, hair or background, within the noise of MIS between sampling and NEE.
TEST(Integrator, PathTracerWhiteFurnace) {
    bcsdf::HairParams params;
    params.sigma_a = glm::dvec3(0.0);
    const Rendered r = tuft_in_white(params);
    for (const glm::vec3& p : r.image.pixels) EXPECT_NEAR(p.x, 1.0f, 0.35f);  // 16 spp noise
    EXPECT_NEAR(mean_radiance(r.image), 1.0, 0.01);
    EXPECT_GT(r.stats.rays, r.image.pixels.size() * 16u);
}

// The same furnace with the Huang fibre (Blender 4.x's hair): its samples carry their weight with a
// density of 1 for MIS, as in Cycles; the lossless fibre's sampled throughput stays within a few
// percent of 1 (huang_test.cpp), so the image does too.
TEST(Integrator, PathTracerWhiteFurnaceWithTheHuangFibre) {
    bcsdf::HairParams params;
    params.fibre = bcsdf::FibreModel::Huang;
    params.huang_sigma_a = glm::dvec3(0.0);
    EXPECT_NEAR(mean_radiance(tuft_in_white(params).image), 1.0, 0.04);
}

// Cycles' Huang closure lets a ray through where it meets the round tube outside the elliptical
// fibre's projected width: black hair in a white environment covers less of the image when flat.
TEST(Integrator, FlatHuangFibresLetRaysPassBesideThem) {
    bcsdf::HairParams params;
    params.fibre = bcsdf::FibreModel::Huang;
    params.huang_sigma_a = glm::dvec3(50.0);
    params.weight_r = 0.0;
    const auto mean = [&](double aspect_ratio) {
        params.aspect_ratio = aspect_ratio;
        return mean_radiance(tuft_in_white(params).image);
    };
    const double round = mean(1.0), flat = mean(0.3);
    EXPECT_LT(round, 0.97);  // the hair is in view and dark
    // The tuft's major axes lie at 45 degrees to this view (the Cycles basis around +x), where a fibre
    // of aspect 0.3 is 0.74 as wide; overlapping strands hide part of the gain. Measured 11 % of the
    // darkening gone; black hair without the pass would not change at all.
    EXPECT_GT(flat - round, 0.05 * (1.0 - round));
}

// Absorbing hair under a directional light, black environment: background black, hair lit,
// everything finite; and the same seed gives the same image bit for bit (tiles run in parallel).
TEST(Integrator, DeterministicPerSeed) {
    HairScene scene(std::make_shared<Device>());
    scene.add_strands(tuft(60, 0.02f));
    scene.commit();
    Lights lights;
    lights.directional.push_back({glm::vec3(0.3f, -0.2f, -1.0f), glm::vec3(3.0f)});
    const bcsdf::HairParams params;
    const Rendered a = render_with(scene, lights, params, Method::PathTrace, 4, 5);
    const Rendered b = render_with(scene, lights, params, Method::PathTrace, 4, 5);
    const Rendered c = render_with(scene, lights, params, Method::PathTrace, 4, 6);
    int lit = 0, differ = 0;
    for (size_t k = 0; k < a.image.pixels.size(); ++k) {
        ASSERT_TRUE(std::isfinite(a.image.pixels[k].x));
        EXPECT_EQ(a.image.pixels[k], b.image.pixels[k]) << k;
        lit += a.image.pixels[k].x > 0.0f;
        differ += a.image.pixels[k] != c.image.pixels[k];
    }
    EXPECT_GT(lit, 20);
    EXPECT_GT(differ, 20);
}

// Dual scattering of a lossless fibre stays bounded (<= the furnace plus the back lobe's d_b share)
// and equals the path tracer's single scattering plus the back lobe: never darker than the direct
// light of the path tracer with no bounces, up to noise.
TEST(Integrator, DualScatteringIsBoundedAndAddsMultipleScattering) {
    HairScene scene(std::make_shared<Device>());
    scene.add_strands(tuft(60, 0.02f));
    scene.commit();
    Lights lights;
    lights.directional.push_back({glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(1.0f)});
    const bcsdf::HairParams params;
    const Rendered ds = render_with(scene, lights, params, Method::DualScattering, 16);
    RenderOptions direct_only;
    direct_only.max_bounces = 0;
    direct_only.spp = 16;
    const Image direct = render(scene, kCamera, lights, params, direct_only);
    double sum_ds = 0.0, sum_direct = 0.0;
    for (size_t k = 0; k < ds.image.pixels.size(); ++k) {
        ASSERT_TRUE(std::isfinite(ds.image.pixels[k].x));
        sum_ds += ds.image.pixels[k].x;
        sum_direct += direct.pixels[k].x;
    }
    EXPECT_GT(sum_ds, 0.9 * sum_direct);
    EXPECT_LT(sum_ds, 5.0 * sum_direct);
}

// The LoD methods on thick hairs: the lossless aggregated BCSDF in the white furnace stays at or below
// the environment (Huang et al. Sec. 4 conserves energy), and every method gives finite images.
TEST(Integrator, LodMethodsOnThickHairs) {
    HairScene scene(std::make_shared<Device>());
    scene.add_thick_hairs(thick_tuft());
    scene.commit();
    Lights lights;
    lights.environment = Environment(glm::vec3(1.0f));
    bcsdf::HairParams lossless;
    lossless.sigma_a = glm::dvec3(0.0);
    const Rendered lod = render_with(scene, lights, lossless, Method::LodAggregated, 8);
    double sum = 0.0;
    for (const glm::vec3& p : lod.image.pixels) sum += p.x;
    EXPECT_LT(sum / lod.image.pixels.size(), 1.02);
    EXPECT_GT(sum / lod.image.pixels.size(), 0.8);
    lights.environment = Environment();
    lights.points.push_back({glm::vec3(0.0f, 2.0f, 3.0f), glm::vec3(10.0f)});
    for (Method m : {Method::LodAggregated, Method::LodSingle, Method::LodNoShadowing}) {
        const Rendered r = render_with(scene, lights, bcsdf::HairParams{}, m, 2);
        double lit = 0.0;
        for (const glm::vec3& p : r.image.pixels) {
            ASSERT_TRUE(std::isfinite(p.x) && p.x >= 0.0f);
            lit += p.x;
        }
        EXPECT_GT(lit, 0.0) << int(m);
    }
}

TEST(Integrator, RejectsBadOptions) {
    HairScene scene(std::make_shared<Device>());
    scene.add_strands(tuft(2, 0.02f));
    scene.commit();
    RenderOptions options;
    options.spp = 0;
    EXPECT_THROW(render(scene, kCamera, Lights{}, bcsdf::HairParams{}, options), Error);
    EXPECT_THROW(parse_method("bdpt"), Error);
    EXPECT_THROW(PinholeCamera({0, 0, 0}, {0, 0, 0}, {0, 0, 1}, 0.5f, 8, 8), Error);
}

}  // namespace
}  // namespace hairlod::render
