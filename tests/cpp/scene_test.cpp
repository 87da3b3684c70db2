#include "hairlod/render/scene.h"

#include <cmath>
#include <limits>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "hairlod/core/error.h"

namespace hairlod::render {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

StrandSet straight_strands(const std::vector<glm::vec3>& starts, float radius) {
    StrandSet s;
    for (const glm::vec3& p : starts) {
        const std::vector<glm::vec3> pts{p + glm::vec3(-2, 0, 0), p + glm::vec3(-0.5f, 0, 0), p + glm::vec3(1, 0, 0),
                                         p + glm::vec3(2, 0, 0)};
        s.add_curve(pts, std::vector<float>(4, radius));
    }
    return s;
}

TEST(HairScene, StrandHitsMatchTheTube) {
    HairScene scene(std::make_shared<Device>());
    scene.add_strands(straight_strands({glm::vec3(0.0f)}, 0.1f));
    scene.commit();
    EXPECT_EQ(scene.segment_count(CurveKind::Strand), 3u);
    for (float y : {0.0f, 0.05f, -0.09f, 0.11f, 0.3f}) {
        SurfaceHit hit;
        const bool found = scene.intersect({0.2f, y, 5.0f}, {0, 0, -1}, kInf, {}, hit);
        EXPECT_EQ(found, std::abs(y) < 0.1f) << y;
        if (!found) continue;
        EXPECT_NEAR(hit.t, 5.0f - std::sqrt(0.01f - y * y), 2e-3f) << y;
        EXPECT_NEAR(std::abs(hit.tangent.x), 1.0f, 1e-4f);
        EXPECT_NEAR(hit.radius, 0.1f, 1e-5f);
        EXPECT_NEAR(glm::length(hit.normal), 1.0f, 1e-4f);
    }
}

// One thick hair along x from -2 to 2, its major axis along y, with constant radii and density.
ThickHairs straight_thick_hair(glm::vec2 radii, float density, float n_total) {
    ThickHairs hairs;
    hairs.centres = {{-2, 0, 0}, {-0.5f, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    hairs.offsets = {0, 4};
    hairs.major_axis.assign(4, glm::vec3(0, 1, 0));
    hairs.radii.assign(4, radii);
    hairs.density.assign(4, density);
    hairs.n_total = {n_total};
    return hairs;
}

TEST(HairScene, ThickHairKeepsOnlyTheEllipse) {
    // Packed so densely that every chord meets a hair (hit probability 1 - exp(-30) at the shortest).
    HairScene scene(std::make_shared<Device>());
    scene.add_thick_hairs(straight_thick_hair({2.0f, 0.5f}, 1.0f, 1e5f));
    scene.commit();
    struct Ray { glm::vec3 origin, direction; float chord; };
    const std::vector<Ray> rays{{{0.1f, 0.0f, 10.0f}, {0, 0, -1}, 1.0f},
                                {{0.1f, 1.9f, 10.0f}, {0, 0, -1}, 2.0f * 0.5f * std::sqrt(1.0f - 0.95f * 0.95f)},
                                {{0.1f, 10.0f, 0.4f}, {0, -1, 0}, 2.0f * 2.0f * std::sqrt(1.0f - 0.8f * 0.8f)},
                                {{0.1f, 10.0f, 0.6f}, {0, -1, 0}, 0.0f},   // inside the round tube, outside the ellipse
                                {{2.6f, 0.0f, 10.0f}, {0, 0, -1}, 0.0f},   // past the last point, in the tube's cap
                                {{-2.4f, 0.3f, 10.0f}, {0, 0, -1}, 0.0f},  // before the first point, in the cap
                                // Oblique from beyond the end into the hair: only the part inside x <= 2
                                // counts (z from 0 down to -0.5), measured in the section's plane.
                                {{2.3f, 0.0f, 0.3f}, glm::normalize(glm::vec3(-1, 0, -1)), 0.5f}};
    for (const Ray& r : rays) {
        SurfaceHit hit;
        const bool found = scene.intersect(r.origin, r.direction, kInf, {}, hit);
        EXPECT_EQ(found, r.chord > 0.0f) << r.origin.y << " " << r.origin.z;
        if (!found) continue;
        EXPECT_EQ(hit.kind, CurveKind::Thick);
        EXPECT_NEAR(hit.chord, r.chord, 2e-3f);
        EXPECT_FLOAT_EQ(hit.n_total, 1e5f);
        EXPECT_NEAR(hit.density, 1.0f, 1e-6f);
        EXPECT_EQ(scene.occluded(r.origin, r.direction, kInf, {}), true);
    }
}

// A ray leaving a strand inside a thick hair meets the hair's next strand at a Poisson arrival of the
// strands it would cross on its way out (own_hair_passage): the arrival places it along the ray, the
// hit is on the same hair, and an arrival past the hair's total means the ray leaves first.
TEST(HairScene, StrandInsideTheHairLiesAtItsArrival) {
    HairScene scene(std::make_shared<Device>());
    scene.add_thick_hairs(straight_thick_hair({2.0f, 0.5f}, 0.05f, 200.0f));
    scene.commit();
    SurfaceHit hit;
    ASSERT_TRUE(scene.intersect({0.1f, 0.0f, 10.0f}, {0, 0, -1}, kInf, {}, hit));
    ASSERT_EQ(hit.kind, CurveKind::Thick);
    const glm::vec3 along_major(0, -1, 0);
    const HairPassage way_out = scene.own_hair_passage(hit, along_major);
    // From (0.1, 0, z) along -y the ellipse's exit is at y = -2 sqrt(1 - (z / 0.5)^2).
    const float exit = 2.0f * std::sqrt(1.0f - hit.position.z * hit.position.z / 0.25f);
    ASSERT_GT(way_out.expected, 1.0);
    EXPECT_NEAR(way_out.chord, exit, 2e-3f);
    for (const double fraction : {0.0, 0.25, 0.5, 0.9}) {
        SurfaceHit next;
        ASSERT_TRUE(scene.strand_inside(hit, along_major, fraction * way_out.expected, next)) << fraction;
        EXPECT_EQ(next.kind, CurveKind::Thick);
        EXPECT_EQ(next.geometry, hit.geometry);
        EXPECT_EQ(next.curve, hit.curve);
        // Constant density along this path: the arrival's share of the count is its share of the chord.
        EXPECT_NEAR(next.t, fraction * exit, 2e-3f) << fraction;
        EXPECT_NEAR(glm::distance(next.position, hit.position + next.t * along_major), 0.0f, 1e-5f);
        EXPECT_NEAR(next.strands_behind, (1.0 - fraction) * way_out.expected, 1e-3 * way_out.expected) << fraction;
        EXPECT_NEAR(next.density, 0.05f, 1e-6f);
    }
    SurfaceHit beyond;
    EXPECT_FALSE(scene.strand_inside(hit, along_major, 1.01 * way_out.expected, beyond));
}

// Brute force: the strands of a sparse cluster, placed uniformly at random in an ellipse, against the
// thick hair standing for them. The thick hair must let as many rays through its gaps as the strands
// do (an opaque ellipse stops every ray that crosses it: hit fraction 1 against about 0.6 here).
void expect_thick_hair_gaps_like_its_strands(float r, double tolerance, double relative_tolerance) {
    const glm::vec2 radii(1.0f, 0.4f);
    const int n_total = 80;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::vector<glm::vec3> starts;
    while (static_cast<int>(starts.size()) < n_total) {
        const float y = unit(rng), z = unit(rng);
        if (y * y + z * z <= 1.0f) starts.emplace_back(0.0f, radii.x * y, radii.y * z);
    }
    HairScene strands(std::make_shared<Device>());
    strands.add_strands(straight_strands(starts, r));
    strands.commit();
    const float density = n_total * r * r / (radii.x * radii.y);  // Sec. 4's rho
    HairScene thick(std::make_shared<Device>());
    thick.add_thick_hairs(straight_thick_hair(radii, density, float(n_total)));
    thick.commit();
    // Parallel rays over the ellipse's shadow, along the minor axis (z) and the major axis (y), each
    // from many x along the fibres (the same gaps, fresh random choices for the thick hair); then
    // the same two at about 31 degrees from the fibres, whose paths through the ellipse are twice
    // as long in 3D but cross no more strands than their projection onto the cross-section does.
    for (const glm::vec3 direction : {glm::vec3(0, 0, -1), glm::vec3(0, -1, 0), glm::normalize(glm::vec3(1.66f, 0, -1)),
                                      glm::normalize(glm::vec3(1.66f, -1, 0))}) {
        const glm::vec3 across = direction.z != 0.0f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
        const float extent = direction.z != 0.0f ? radii.x : radii.y;
        int crossing = 0, strand_hits = 0, thick_hits = 0;
        for (int k = 0; k < 4000; ++k) {
            const float offset = extent * (-0.995f + 1.99f * (k + 0.5f) / 4000.0f);
            for (int j = 0; j < 5; ++j) {
                const glm::vec3 origin = glm::vec3(-0.9f + 0.35f * j, 0, 0) + offset * across - 10.0f * direction;
                ++crossing;
                strand_hits += strands.occluded(origin, direction, kInf, {});
                SurfaceHit hit;
                thick_hits += thick.intersect(origin, direction, kInf, {}, hit);
            }
        }
        const double strand_fraction = double(strand_hits) / crossing, thick_fraction = double(thick_hits) / crossing;
        EXPECT_GT(strand_fraction, 0.0);
        EXPECT_NEAR(thick_fraction, strand_fraction, tolerance + relative_tolerance * strand_fraction)
            << "r " << r << " direction " << direction.x << " " << direction.y;
    }
}

TEST(HairScene, SparseThickHairLetsRaysThroughLikeItsStrands) {
    // rho = 0.08: across the thin side the strands stop about 0.6 of the rays (an opaque ellipse: all).
    expect_thick_hair_gaps_like_its_strands(0.02f, 0.06, 0.0);
}

TEST(HairScene, VerySparseThickHairLetsRaysThroughLikeItsStrands) {
    // rho = 5e-5, as on real hair (strands of radius 1e-4 in clusters centimetres across): about 4 %
    // of the rays meet a strand. A floor on rho (once 1e-3) would make the thick hair stop 4.5x more.
    expect_thick_hair_gaps_like_its_strands(0.0005f, 0.004, 0.2);
}

TEST(HairScene, CountsEveryCrossedStrandOnce) {
    std::vector<glm::vec3> starts;
    for (int k = 0; k < 5; ++k) starts.emplace_back(0.0f, 0.0f, float(k));
    HairScene scene(std::make_shared<Device>());
    scene.add_strands(straight_strands(starts, 0.05f));
    scene.commit();
    EXPECT_EQ(scene.count_crossings({0.3f, 0.01f, 10.0f}, {0, 0, -1}, kInf, {}), 5);
    EXPECT_EQ(scene.count_crossings({0.3f, 0.01f, 10.0f}, {0, 0, -1}, 8.5f, {}), 3);  // stops at t_max (z = 1.5)
    EXPECT_EQ(scene.count_crossings({0.3f, 0.01f, 10.0f}, {0, 0, -1}, kInf, {}, 3), 3);
    EXPECT_EQ(scene.count_crossings({0.3f, 0.5f, 10.0f}, {0, 0, -1}, kInf, {}), 0);
    // Leaving the top strand downwards through itself: its own tube is skipped.
    SurfaceHit hit;
    ASSERT_TRUE(scene.intersect({0.3f, 0.01f, 10.0f}, {0, 0, -1}, kInf, {}, hit));
    EXPECT_NEAR(hit.position.z, 4.05f, 2e-3f);
    const glm::vec3 down(0, 0, -1);
    EXPECT_EQ(scene.count_crossings(hit.position, down, kInf, scene.leaving(hit, down)), 4);
    EXPECT_FALSE(scene.occluded(hit.position, -down, kInf, scene.leaving(hit, -down)));
}

TEST(HairScene, RejectsInvalidInput) {
    HairScene scene(std::make_shared<Device>());
    EXPECT_THROW(scene.add_strands(straight_strands({glm::vec3(0.0f)}, 0.0f)), Error);
    ThickHairs hairs;
    hairs.centres = {{0, 0, 0}, {1, 0, 0}};
    hairs.offsets = {0, 2};
    hairs.major_axis.assign(2, glm::vec3(0, 1, 0));
    hairs.radii.assign(2, glm::vec2(0.5f, 1.0f));  // minor > major
    hairs.density.assign(2, 0.5f);
    hairs.n_total = {3.0f};
    EXPECT_THROW(scene.add_thick_hairs(hairs), Error);
}

}  // namespace
}  // namespace hairlod::render
