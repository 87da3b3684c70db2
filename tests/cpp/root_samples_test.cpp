#include "hairlod/hairmesh/root_samples.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "hairlod/hairmesh/hair_mesh.h"
#include "hairlod/hairmesh/hash_random.h"
#include "hairmesh_fixtures.h"

namespace hairlod {
namespace {

std::vector<glm::vec2> white_noise(size_t count, uint64_t seed, bool triangle) {
    RandomStream random(seed);
    std::vector<glm::vec2> points(count);
    for (glm::vec2& p : points) {
        p = {random.next_unit(), random.next_unit()};
        if (triangle && p.x + p.y >= 1.0f) p = {1.0f - p.x, 1.0f - p.y};
    }
    return points;
}

// Blue noise: every prefix of the progressive set spreads its points at least 1.5x further apart
// (mean nearest-neighbour distance) than uniform random points of the same count.
TEST(RootSamples, EveryPrefixIsBlueNoise) {
    for (SampleDomain domain : {SampleDomain::UnitSquare, SampleDomain::UnitTriangle}) {
        const std::vector<glm::vec2> samples = progressive_blue_noise(1024, domain, 11);
        ASSERT_EQ(samples.size(), 1024u);
        const bool triangle = domain == SampleDomain::UnitTriangle;
        for (size_t count : {32u, 100u, 256u, 700u, 1024u}) {
            const std::vector<glm::vec2> prefix(samples.begin(), samples.begin() + count);
            const double blue = test::mean_nearest_neighbour(prefix);
            // The expected white-noise distance, averaged over 16 realisations.
            double white = 0.0;
            for (uint64_t seed = 0; seed < 16; ++seed) white += test::mean_nearest_neighbour(white_noise(count, 100 * seed + count, triangle)) / 16.0;
            EXPECT_GE(blue, 1.5 * white) << "count " << count << (triangle ? " triangle" : " square");
        }
    }
}

TEST(RootSamples, StayInTheirDomain) {
    for (const glm::vec2& p : progressive_blue_noise(500, SampleDomain::UnitSquare, 3)) {
        EXPECT_GE(std::min(p.x, p.y), 0.0f);
        EXPECT_LT(std::max(p.x, p.y), 1.0f);
    }
    for (const glm::vec2& p : progressive_blue_noise(500, SampleDomain::UnitTriangle, 3)) {
        EXPECT_GE(std::min(p.x, p.y), 0.0f);
        EXPECT_LE(p.x + p.y, 1.0f);
    }
}

TEST(RootSamples, DeterministicPerSeed) {
    EXPECT_EQ(progressive_blue_noise(300, SampleDomain::UnitSquare, 5), progressive_blue_noise(300, SampleDomain::UnitSquare, 5));
    EXPECT_NE(progressive_blue_noise(300, SampleDomain::UnitSquare, 5), progressive_blue_noise(300, SampleDomain::UnitSquare, 6));
}

// Sec. 3.3: bilinear interpolation with xi^Delta over a triangle whose third vertex is duplicated
// equals barycentric interpolation with weights (1 - xi_s - xi_t, xi_s, xi_t).
TEST(RootSamples, TriangleMappingIsBarycentric) {
    const glm::vec3 a{0.3f, -1, 2}, b{4, 0.5f, 1}, c{-2, 3, 0.25f};
    for (const glm::vec2& xi : progressive_blue_noise(200, SampleDomain::UnitTriangle, 8)) {
        const glm::vec2 st = triangle_to_square(xi);
        ASSERT_GE(std::min(st.x, st.y), 0.0f);
        ASSERT_LE(std::max(st.x, st.y), 1.0f);
        const auto w = bilinear_weights(st.x, st.y);
        const glm::vec3 bilinear = w[0] * a + w[1] * b + (w[2] + w[3]) * c;
        const glm::vec3 barycentric = (1.0f - xi.x - xi.y) * a + xi.x * b + xi.y * c;
        EXPECT_LT(glm::distance(bilinear, barycentric), 1e-5f);
    }
}

TEST(RootSamples, BundlesUseDifferentPatterns) {
    const RootSampleSets sets = make_root_sample_sets(64, 4, 1);
    int identical = 0;
    for (uint64_t bundle = 1; bundle < 20; ++bundle) {
        bool same = true;
        for (size_t i = 0; i < 16; ++i) same = same && sets.root_coordinates(bundle, i, false) == sets.root_coordinates(0, i, false);
        identical += same;
    }
    // 32 (set, symmetry) choices: a few of 19 bundles may repeat bundle 0's pattern, most must not.
    EXPECT_LE(identical, 4);
    for (uint64_t bundle = 0; bundle < 20; ++bundle)
        for (size_t i = 0; i < 64; ++i)
            for (bool triangle : {false, true}) {
                const glm::vec2 st = sets.root_coordinates(bundle, i, triangle);
                ASSERT_TRUE(st.x >= 0.0f && st.x <= 1.0f && st.y >= 0.0f && st.y <= 1.0f);
            }
}

}  // namespace
}  // namespace hairlod
