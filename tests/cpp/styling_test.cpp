#include "hairlod/hairmesh/styling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

// One vertex at height w above the centre curve point (0, 0, w), offset 0.3 along x, with the
// frame u = x, v = y, w = z.
StrandVertices vertex_at(float w, float t) {
    StrandVertices vertex;
    vertex.resize(1);
    vertex.set_vec3(StrandVertices::X, 0, {0.3f, 0.0f, w});
    vertex.set_vec3(StrandVertices::UX, 0, {1, 0, 0});
    vertex.set_vec3(StrandVertices::VX, 0, {0, 1, 0});
    vertex.set_vec3(StrandVertices::WX, 0, {0, 0, 1});
    vertex.set_vec3(StrandVertices::CX, 0, {0, 0, w});
    vertex[StrandVertices::W_FROM_ROOT][0] = w;
    vertex[StrandVertices::T][0] = t;
    return vertex;
}

glm::vec3 offset(const std::vector<StylingOperation>& ops, uint64_t strand, float w, float t) {
    StrandStyling styling;
    draw_strand_styling(ops, 5, strand, styling);
    StrandVertices vertex = vertex_at(w, t);
    const glm::vec3 before = vertex.vec3(StrandVertices::X, 0);
    apply_styling(ops, styling, vertex, 0);
    return vertex.vec3(StrandVertices::X, 0) - before;
}

const std::vector<StylingOperation> kAll{Curl{0.2f, 3.0f, 0.5f}, Wave{0.3f, 1.5f, 1.0f}, Twist{0.5f},
                                          Clump{0.6f, 2.0f},      Frizz{0.05f, 8.0f},      Trim{0.3f}};

TEST(Styling, RootsDoNotMove) {
    for (uint64_t strand = 0; strand < 50; ++strand) EXPECT_LT(glm::length(offset(kAll, strand, 0.0f, 0.0f)), 1e-6f);
}

TEST(Styling, CurlIsAHelixOfTheGivenRadius) {
    const std::vector<StylingOperation> curl{Curl{0.2f, 2.0f, 0.0f}};
    // Phases up to 2 pi 2 300 ~ 3800 rad exercise the sin/cos range reduction.
    for (float w : {0.1f, 0.25f, 0.6f, 7.3f, 41.0f, 299.9f}) {
        // Without randomness phi0 = 0: offset = r (cos phi - 1, sin phi, 0), phi = 2 pi f w.
        const double phi = 2.0 * 3.14159265358979 * 2.0 * w;
        const glm::vec3 expected = 0.2f * glm::vec3(std::cos(phi) - 1.0, std::sin(phi), 0.0);
        // The float phase 2 pi f w itself carries a relative error of ~1e-7, i.e. ~4e-4 rad at 3800 rad.
        EXPECT_LT(glm::distance(offset(curl, 3, w, std::min(w, 1.0f)), expected), 1e-5f + 0.2f * 1.2e-7f * float(phi)) << w;
    }
}

TEST(Styling, AmplitudesAreObjectSpace) {
    // The offsets stay within their stated amplitude bounds whatever the frame scale of the mesh.
    for (uint64_t strand = 0; strand < 100; ++strand)
        for (float w = 0.0f; w < 3.0f; w += 0.1f) {
            EXPECT_LE(glm::length(offset({Curl{0.2f, 3.0f, 1.0f}}, strand, w, 0.5f)), 2.0f * 0.2f * 1.5f + 1e-5f);
            EXPECT_LE(glm::length(offset({Wave{0.3f, 1.5f, 1.0f}}, strand, w, 0.5f)), 2.0f * 0.3f + 1e-5f);
            EXPECT_LE(glm::length(offset({Frizz{0.05f, 8.0f}}, strand, w, 0.5f)), 2.0f * 0.05f * std::sqrt(3.0f) + 1e-5f);
        }
}

TEST(Styling, ClumpPullsTowardsTheCentreWithItsProfile) {
    const std::vector<StylingOperation> clump{Clump{1.0f, 2.0f}};
    EXPECT_LT(glm::distance(offset(clump, 0, 1.0f, 1.0f), glm::vec3(-0.3f, 0, 0)), 1e-6f);
    EXPECT_LT(glm::distance(offset(clump, 0, 1.0f, 0.5f), glm::vec3(-0.3f * 0.25f, 0, 0)), 1e-6f);
}

TEST(Styling, TwistRotatesAboutTheCentre) {
    const glm::vec3 moved = offset({Twist{0.25f}}, 0, 1.0f, 1.0f) + vertex_at(1.0f, 1.0f).vec3(StrandVertices::X, 0);
    EXPECT_LT(glm::distance(moved, glm::vec3(0.0f, 0.3f, 1.0f)), 1e-6f);  // a quarter turn
}

TEST(Styling, TrimShortensWithinItsRange) {
    const std::vector<StylingOperation> trim{Trim{0.3f}}, none{Trim{0.0f}};
    StrandStyling styling;
    for (uint64_t strand = 0; strand < 100; ++strand) {
        draw_strand_styling(trim, 1, strand, styling);
        EXPECT_GE(styling.length_fraction, 0.7f);
        EXPECT_LE(styling.length_fraction, 1.0f);
    }
    draw_strand_styling(none, 1, 4, styling);
    EXPECT_EQ(styling.length_fraction, 1.0f);
}

TEST(Styling, DeterministicAndVariedPerStrand) {
    EXPECT_EQ(offset(kAll, 7, 1.3f, 0.6f), offset(kAll, 7, 1.3f, 0.6f));
    EXPECT_NE(offset(kAll, 7, 1.3f, 0.6f), offset(kAll, 8, 1.3f, 0.6f));
}

TEST(Styling, FrizzIsContinuousAlongTheStrand) {
    const std::vector<StylingOperation> frizz{Frizz{0.05f, 8.0f}};
    // Lipschitz bound of the C1 value noise: smoothstep slope 1.5 times a lattice step of at most 2,
    // per component, so |d offset / dw| <= amplitude frequency 3 sqrt(3).
    for (float w = 0.0f; w < 2.0f; w += 0.01f)
        EXPECT_LT(glm::distance(offset(frizz, 2, w, 0.5f), offset(frizz, 2, w + 1e-4f, 0.5f)),
                  0.05f * 8.0f * 1e-4f * 3.0f * std::sqrt(3.0f) * 1.01f);
}

// Frizz hashes its lattice once per strand, or per vertex when the noise is far finer than the
// vertices; both must give value noise's offset, so a vertex moves the same alone or beside a far one.
TEST(Styling, FrizzIsTheSameWhicheverWayTheLatticeIsHashed) {
    const std::vector<StylingOperation> frizz{Frizz{0.05f, 8.0f}};
    StrandStyling styling;
    draw_strand_styling(frizz, 5, 3, styling);
    for (float w : {0.3f, 1.7f, 5.25f}) {
        StrandVertices alone = vertex_at(w, 0.5f);
        apply_styling(frizz, styling, alone, 0);
        StrandVertices pair;  // the second vertex 100 cells away: the per-vertex path
        pair.resize(2);
        for (size_t k = 0; k < 2; ++k) {
            const StrandVertices one = vertex_at(k == 0 ? w : w + 100.0f / 8.0f, 0.5f);
            for (int c = 0; c < StrandVertices::kComponentCount; ++c)
                pair[StrandVertices::Component(c)][k] = one[StrandVertices::Component(c)][0];
        }
        apply_styling(frizz, styling, pair, 0);
        EXPECT_EQ(pair.vec3(StrandVertices::X, 0), alone.vec3(StrandVertices::X, 0)) << w;
    }
}

// Clump's per-vertex t^profile is kept between strands; a new t or profile must not reuse it.
TEST(Styling, ClumpRecomputesItsProfileWhenTOrTheProfileChange) {
    StrandStyling styling;
    for (const auto& [profile, t] : {std::pair{2.0f, 0.5f}, {2.0f, 0.25f}, {3.0f, 0.25f}, {3.0f, 0.25f}}) {
        const std::vector<StylingOperation> clump{Clump{1.0f, profile}};
        draw_strand_styling(clump, 5, 0, styling);
        StrandVertices vertex = vertex_at(1.0f, t);
        apply_styling(clump, styling, vertex, 0);
        EXPECT_NEAR(vertex.vec3(StrandVertices::X, 0).x, 0.3f * (1.0f - std::pow(t, profile)), 1e-6f) << profile << " " << t;
    }
}

TEST(Styling, ValidationNamesTheOperation) {
    const std::vector<StylingOperation> bad{Curl{0.1f, 1.0f, 0.0f}, Clump{1.5f, 1.0f}};
    try {
        validate_styling(bad);
        FAIL();
    } catch (const Error& error) {
        EXPECT_STREQ(error.what(), "styling operation 1 (clump): amount must be in [0, 1]");
    }
    EXPECT_THROW(validate_styling(std::vector<StylingOperation>{Curl{NAN, 1.0f, 0.0f}}), Error);
    EXPECT_THROW(validate_styling(std::vector<StylingOperation>{Clump{0.5f, 0.0f}}), Error);
    EXPECT_NO_THROW(validate_styling(kAll));
}

}  // namespace
}  // namespace hairlod
