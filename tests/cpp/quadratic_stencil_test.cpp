#include "hairlod/lod/quadratic_stencil.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "hairlod/lod/skinning.h"
#include "hanging_hair.h"

namespace hairlod {
namespace {

constexpr int kControlPoints = 8;

// A neck bending about the x axis, more towards the tips (as bench skinning's).
glm::vec3 bend(const glm::vec3& p) {
    const float angle = 0.5f * std::max(0.0f, 1.0f - p.z);
    const float c = std::cos(angle), s = std::sin(angle);
    return {p.x, c * p.y - s * p.z, s * p.y + c * p.z};
}

// A global affine map that is not rigid: stretch and shear.
glm::vec3 stretch(const glm::vec3& p) {
    const glm::mat3 linear(glm::vec3(1.2f, 0.0f, 0.1f), glm::vec3(0.3f, 0.9f, 0.0f), glm::vec3(0.0f, 0.2f, 1.1f));
    return linear * p + glm::vec3(0.4f, -0.1f, 0.2f);
}

// A global quadratic motion: a bulge and a twist growing with the square of the distance.
glm::vec3 quadratic(const glm::vec3& p) {
    return stretch(p) + glm::vec3(0.15f * p.x * p.x - 0.1f * p.y * p.z, 0.2f * p.x * p.z + 0.05f * p.y * p.y,
                                  -0.1f * p.z * p.z + 0.1f * p.x * p.y);
}

glm::vec3 rigid(const glm::vec3& p) {
    static const glm::mat4 motion = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, -2.0f, 3.0f)), 0.7f,
                                                glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)));
    return glm::vec3(motion * glm::vec4(p, 1.0f));
}

template <typename Map>
std::vector<glm::vec3> moved(std::vector<glm::vec3> points, Map map) {
    for (glm::vec3& p : points) p = map(p);
    return points;
}

double percentile(std::vector<double> values, double q) {
    std::sort(values.begin(), values.end());
    return values[static_cast<size_t>(q * static_cast<double>(values.size() - 1))];
}

struct Errors {
    std::vector<double> stencil, prism, best_affine;  // per strand point, distance to the truth
};

// Per strand point (input order): the distance of the skinned point to the same rest point moved by
// `deformation`, for the stencils (LodAsset::skin), for the paper's prism map alone (the frame of
// the cluster's 3 guides) and for the best affine map of each cluster and control point fitted to
// the moved points themselves (least squares, brute force: the floor for one map per cluster).
template <typename Map>
Errors following_errors(const LodAsset& a, Map deformation) {
    const size_t nc = kControlPoints;
    const std::vector<glm::vec3> rest = a.rest_geometry().strands.points;
    const std::vector<glm::vec3> guides = moved(a.rest_guides, deformation);
    const std::vector<glm::vec3> skinned = a.skin(guides).strands.points;
    const SkinningRest skin_rest = skinning_rest(a);
    Errors errors;
    for (size_t c = 0; c < a.cluster_count(); ++c) {
        const auto [first, end] = a.cluster_strands(c);
        const GuideSet deformed = guide_set(a.cluster_guides[c], guides.data(), a.control_points);
        for (size_t k = 0; k < nc; ++k) {
            const GuideFrame& rest_frame = skin_rest.frames[c * nc + k];
            const GuideFrame frame = guide_frame(a.frame_kinds[c * nc + k], deformed, static_cast<int>(k));
            const glm::mat3 prism = frame_map(rest_frame, frame);
            // Normal equations of the best affine map, in double around the first point.
            const glm::dvec3 anchor(rest[static_cast<size_t>(a.strand_order[static_cast<size_t>(first)]) * nc + k]);
            glm::dmat4 gram(0.0);
            glm::dmat4x3 moments(0.0);  // sum moved * X^T
            for (int32_t i = first; i < end; ++i) {
                const size_t at = static_cast<size_t>(a.strand_order[static_cast<size_t>(i)]) * nc + k;
                const glm::dvec4 x(glm::dvec3(rest[at]) - anchor, 1.0);
                gram += glm::outerProduct(x, x);
                moments += glm::outerProduct(glm::dvec3(deformation(rest[at])), x);
            }
            // A faint ridge settles the directions in which the cluster's points do not spread.
            for (int d = 0; d < 3; ++d) gram[d][d] += 1e-12;
            const glm::dmat4x3 best = moments * glm::inverse(gram);
            for (int32_t i = first; i < end; ++i) {
                const size_t at = static_cast<size_t>(a.strand_order[static_cast<size_t>(i)]) * nc + k;
                const glm::vec3 truth = deformation(rest[at]);
                errors.stencil.push_back(glm::distance(skinned[at], truth));
                errors.prism.push_back(glm::distance(frame.origin + prism * (rest[at] - rest_frame.origin), truth));
                errors.best_affine.push_back(
                    glm::distance(glm::dvec3(truth), best * glm::dvec4(glm::dvec3(rest[at]) - anchor, 1.0)));
            }
        }
    }
    return errors;
}

class QuadraticStencilTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        asset_ = new LodAsset(build_lod(testing::wavy_hair(4000, 12, 3),
                                        {.guides = 48, .levels = 3, .control_points = kControlPoints, .seed = 1}));
    }
    static void TearDownTestSuite() { delete asset_; }
    static LodAsset* asset_;
    static constexpr double kSize = 3.0;  // about the hair's extent: tolerances are relative to it
};
LodAsset* QuadraticStencilTest::asset_ = nullptr;

// A smooth non-rigid motion is followed more closely than one affine map per cluster could (the
// best one fitted to the moved strands themselves: 0.51x its p99 measured), and far more closely
// than the prism of 3 guides.
TEST_F(QuadraticStencilTest, ABendIsFollowedMoreCloselyThanByTheBestAffineMapPerCluster) {
    const Errors e = following_errors(*asset_, bend);
    const double stencil = percentile(e.stencil, 0.99), prism = percentile(e.prism, 0.99),
                 floor = percentile(e.best_affine, 0.99);
    EXPECT_LT(stencil, 0.6 * floor) << "stencil p99 " << stencil << ", best affine p99 " << floor;
    EXPECT_LT(stencil, 0.25 * prism) << "stencil p99 " << stencil << ", prism p99 " << prism;
    EXPECT_LT(percentile(e.stencil, 1.0), 0.25 * percentile(e.prism, 1.0));
}

// A stretch and shear of the whole hair is an affine map, and a quadratic motion is in the fields'
// span: the stencils reproduce both (the prism, whose third axis stays a unit normal, cannot, and
// no affine map per cluster follows the quadratic one).
TEST_F(QuadraticStencilTest, GlobalAffineAndQuadraticMotionsAreReproduced) {
    const Errors affine = following_errors(*asset_, stretch);
    EXPECT_LT(percentile(affine.stencil, 1.0), 1e-4 * kSize);
    EXPECT_GT(percentile(affine.prism, 1.0), 100.0 * percentile(affine.stencil, 1.0));
    const Errors curved = following_errors(*asset_, quadratic);
    EXPECT_LT(percentile(curved.stencil, 1.0), 1e-4 * kSize);
    EXPECT_GT(percentile(curved.best_affine, 1.0), 10.0 * percentile(curved.stencil, 1.0));
}

// Where the guides leave directions open (1 or 2 guides, a straight or coincident set), the prism
// map decides them: rigid motions stay exact with any number of guides.
TEST(QuadraticStencilFewGuides, RigidMotionsStayExact) {
    for (int guides : {1, 2, 3}) {
        const LodAsset a = build_lod(testing::wavy_hair(300, 10, 5), {.guides = guides, .levels = 2, .control_points = 6, .seed = 3});
        const std::vector<glm::vec3> rest = a.rest_geometry().strands.points;
        const std::vector<glm::vec3> skinned = a.skin(moved(a.rest_guides, rigid)).strands.points;
        for (size_t i = 0; i < rest.size(); ++i)
            ASSERT_LT(glm::distance(skinned[i], rigid(rest[i])), 1e-5f * 8.0f) << guides << " guides, point " << i;
    }
}

// Every term and prior weight is finite, on identical strands (all guides coincide: h has no
// scale) as on ordinary hair, and the rest pose maps to itself.
TEST(QuadraticStencilFewGuides, CoincidentGuidesGiveFiniteWeights) {
    StrandSet strands;
    const std::vector<glm::vec3> curve = {{0, 0, 0}, {0, 0, -0.5f}, {0.1f, 0, -1.0f}, {0.2f, 0, -1.4f}};
    for (int i = 0; i < 20; ++i) strands.add_curve(curve, std::vector<float>(curve.size(), 0.01f));
    const LodAsset a = build_lod(strands, {.guides = 4, .levels = 2, .control_points = 4, .seed = 1});
    const SkinningRest rest = skinning_rest(a);
    for (const StencilTerm& term : rest.stencils.terms)
        for (double w : term.weight) ASSERT_TRUE(std::isfinite(w));
    for (const QuadraticStencil& stencil : rest.stencils.stencils)
        for (const FieldWeights& prior : stencil.prior)
            for (double w : prior) ASSERT_TRUE(std::isfinite(w));
    const std::vector<glm::vec3> points = a.rest_geometry().strands.points;
    const std::vector<glm::vec3> turned = a.skin(moved(a.rest_guides, rigid)).strands.points;
    for (size_t i = 0; i < points.size(); ++i) ASSERT_LT(glm::distance(turned[i], rigid(points[i])), 1e-5f * 8.0f);
}

}  // namespace
}  // namespace hairlod
