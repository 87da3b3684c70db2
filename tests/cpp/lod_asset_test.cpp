#include "hairlod/lod/lod_asset.h"

#include "hairlod/lod/cross_section.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <tbb/global_control.h>

#include "hairlod/core/error.h"
#include "hairlod/curves/resample.h"
#include "hanging_hair.h"

namespace hairlod {
namespace {

// The strands as build_lod resamples them: what the rest pose must reproduce.
StrandSet lod_resampled(const StrandSet& strands, int control_points) {
    return resample_strands(strands, {.points_per_curve = control_points,
                                      .subdivisions_per_segment = LodOptions{}.arc_length_subdivisions});
}

float max_relative_error(std::span<const glm::vec3> got, std::span<const glm::vec3> expected) {
    float scale = 1e-30f, error = 0.0f;
    for (const glm::vec3& p : expected) scale = std::max(scale, glm::length(p));
    for (size_t i = 0; i < got.size(); ++i) error = std::max(error, glm::distance(got[i], expected[i]));
    return error / scale;
}

class LodAssetTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        strands_ = new StrandSet(testing::wavy_hair(3000, 12, 1));
        asset_ = new LodAsset(build_lod(*strands_, {.guides = 24, .levels = 6, .control_points = 8, .seed = 3}));
    }
    static void TearDownTestSuite() {
        delete asset_;
        delete strands_;
    }
    static StrandSet* strands_;
    static LodAsset* asset_;
};
StrandSet* LodAssetTest::strands_ = nullptr;
LodAsset* LodAssetTest::asset_ = nullptr;

TEST_F(LodAssetTest, LevelsPartitionTheStrands) {
    const LodAsset& a = *asset_;
    ASSERT_GE(a.thick_levels.size(), 2u);
    EXPECT_EQ(a.guide_count(), 24u);
    for (size_t l = 0; l < a.thick_levels.size(); ++l) {
        const ThickHairLevel& level = a.thick_levels[l];
        int64_t total = 0;
        std::vector<int32_t> counted(level.hair_count(), 0), n_total(level.hair_count());
        for (size_t h = 0; h < level.hair_count(); ++h) total += n_total[h] = level.n_total(h);
        EXPECT_EQ(total, 3000) << "level " << l;
        const std::vector<int32_t> strand_hairs = a.strand_hairs(l);
        for (int32_t h : strand_hairs) ++counted[static_cast<size_t>(h)];
        EXPECT_EQ(counted, n_total);
        EXPECT_EQ(level.cluster_first.back(), static_cast<int32_t>(level.hair_count()));
        // Every strand's hair lies inside the hair of the level above that holds the strand.
        const std::vector<int32_t> coarser = l > 0 ? a.strand_hairs(l - 1) : std::vector<int32_t>{};
        for (size_t s = 0; l > 0 && s < 3000; ++s)
            EXPECT_EQ(level.parent[static_cast<size_t>(strand_hairs[s])], coarser[s]);
    }
    EXPECT_EQ(a.thick_levels[0].hair_count(), a.cluster_count());
}

TEST_F(LodAssetTest, L0ClustersShareTheirThreeNearestGuides) {
    const LodAsset& a = *asset_;
    const StrandSet resampled = lod_resampled(*strands_, 8);
    const std::vector<int32_t> strand_clusters = a.strand_hairs(0);
    for (size_t s = 0; s < 3000; s += 97) {
        std::vector<std::pair<double, int32_t>> distances;
        for (size_t g = 0; g < a.guide_count(); ++g) {
            double d = 0.0;
            for (size_t k = 0; k < 8; ++k) {
                const glm::dvec3 e = glm::dvec3(resampled.points[s * 8 + k]) - glm::dvec3(a.rest_guides[g * 8 + k]);
                d += glm::dot(e, e);
            }
            distances.emplace_back(d, static_cast<int32_t>(g));
        }
        std::sort(distances.begin(), distances.end());
        std::array<int32_t, 3> expected{distances[0].second, distances[1].second, distances[2].second};
        std::sort(expected.begin(), expected.end());
        EXPECT_EQ(a.cluster_guides[static_cast<size_t>(strand_clusters[s])], expected) << "strand " << s;
    }
}

TEST_F(LodAssetTest, CoverageAndAreaRatioPerLevel) {
    const LodAsset& a = *asset_;
    for (size_t l = 0; l < a.thick_levels.size(); ++l) {
        EXPECT_GE(a.thick_levels[l].coverage, 0.95) << "level " << l;
        if (l == 0) continue;
        const double ratio = a.thick_levels[l - 1].mean_area / a.thick_levels[l].mean_area;
        RecordProperty("area_ratio_L" + std::to_string(l), std::to_string(ratio));
        // The strand count shrinks evenly (about 2x here: clusters of about 30 strands over 5
        // levels); the area follows it, faster at the finest levels where a few strands leave less
        // of an ellipse (1.7, 1.9, 2.5, 4.0 measured).
        EXPECT_GT(ratio, 1.5) << "level " << l;
        EXPECT_LT(ratio, 8.0) << "level " << l;
    }
    // Independent recount on L0 from the rest geometry: members crossing their section's plane inside
    // its ellipse.
    const LodGeometry rest = a.rest_geometry();
    const std::vector<int32_t> strand_hairs = a.strand_hairs(0);
    int64_t inside = 0;
    for (size_t s = 0; s < 3000; ++s)
        for (size_t k = 0; k < 8; ++k) {
            const size_t at = static_cast<size_t>(strand_hairs[s]) * 8 + k;
            const glm::vec3 normal = glm::normalize(glm::cross(rest.levels[0].major[at], rest.levels[0].minor[at]));
            const glm::vec3 crossing =
                strand_plane_crossing(std::span(rest.strands.points).subspan(s * 8, 8), k, rest.levels[0].centre[at], normal);
            const glm::vec3 d = crossing - rest.levels[0].centre[at];
            const float u = glm::dot(d, rest.levels[0].major[at]) / glm::dot(rest.levels[0].major[at], rest.levels[0].major[at]);
            const float v = glm::dot(d, rest.levels[0].minor[at]) / glm::dot(rest.levels[0].minor[at], rest.levels[0].minor[at]);
            inside += u * u + v * v <= 1.0f + 1e-4f;
        }
    EXPECT_GE(static_cast<double>(inside) / (3000.0 * 8.0), 0.95);
}

TEST_F(LodAssetTest, CrossSectionsAreAFunctionOfTheStoredStrands) {
    // A file leaves the cross-sections out; fitting them again gives exactly the build's, and the
    // centre is the mean of where the members' decoded strands cross its plane (Sec. 5.1 step 3, at
    // the crossings: cross_section.h).
    const LodAsset& built = *asset_;
    LodAsset read = built;
    for (ThickHairLevel& level : read.thick_levels) {
        ThickHairLevel::visit_section_arrays(level, [](const char*, auto& values) { values.clear(); });
        level.coverage = level.mean_area = 0.0;
    }
    EXPECT_THROW(read.validate(), Error);
    read.validate_structure();
    fit_sections(read);
    read.validate();
    for (size_t l = 0; l < built.thick_levels.size(); ++l) {
        const ThickHairLevel &a = built.thick_levels[l], &b = read.thick_levels[l];
        EXPECT_TRUE(a.centre_offset == b.centre_offset && a.major_axis == b.major_axis && a.minor_axis == b.minor_axis &&
                    a.radii == b.radii)
            << "level " << l;
        EXPECT_EQ(a.coverage, b.coverage);
        EXPECT_EQ(a.mean_area, b.mean_area);
    }
    const LodGeometry rest = read.rest_geometry();
    const ThickHairLevel& finest = read.thick_levels.back();
    int sampled = 0, at_mean = 0;
    for (size_t h = 0; h < finest.hair_count(); h += 7) {
        for (size_t k = 0; k < 8; k += 3) {
            const glm::vec3 centre = rest.levels.back().centre[h * 8 + k];
            const glm::vec3 normal = glm::normalize(glm::cross(rest.levels.back().major[h * 8 + k], rest.levels.back().minor[h * 8 + k]));
            glm::dvec3 points_mean(0.0), crossings_mean(0.0);
            for (int32_t i = finest.member_first[h]; i < finest.member_first[h + 1]; ++i) {
                const auto strand = static_cast<size_t>(read.strand_order[static_cast<size_t>(i)]);
                points_mean += glm::dvec3(rest.strands.points[strand * 8 + k]);
                crossings_mean += glm::dvec3(strand_plane_crossing(std::span(rest.strands.points).subspan(strand * 8, 8), k, centre, normal));
            }
            points_mean /= static_cast<double>(finest.n_total(h));
            crossings_mean /= static_cast<double>(finest.n_total(h));
            // The plane passes through the mean of the members' k-th points; the centre is stored in
            // 16-bit steps of its cluster's box, and the axes (the plane's normal) in 16-bit octahedral
            // codes, so where a wavy member crosses near k twice, the decoded plane may pick the other.
            EXPECT_LT(std::abs(glm::dot(glm::vec3(points_mean) - centre, normal)), 3e-3f) << h << " " << k;
            ++sampled;
            at_mean += glm::distance(glm::vec3(crossings_mean), centre) < 1e-3f ? 1 : 0;
        }
    }
    EXPECT_GE(at_mean, sampled * 3 / 4) << "of " << sampled << " sections, the centre is the mean of its members' crossings";
    read.ellipse_coverage = 0.0f;
    EXPECT_THROW(fit_sections(read), Error);
}

// Hairs per level of each L0 cluster: counts[l][c].
std::vector<std::vector<int32_t>> hairs_per_cluster(const LodAsset& a) {
    std::vector<std::vector<int32_t>> counts;
    for (const ThickHairLevel& level : a.thick_levels) {
        std::vector<int32_t>& row = counts.emplace_back();
        for (size_t c = 0; c < a.cluster_count(); ++c) row.push_back(level.cluster_first[c + 1] - level.cluster_first[c]);
    }
    return counts;
}

TEST_F(LodAssetTest, LevelsAboutFourfoldApartInAreaDownToFourStrandsPerHair) {
    const LodAsset& a = *asset_;
    ASSERT_GE(a.thick_levels.size(), 2u);
    ASSERT_LE(a.thick_levels.size(), 5u);  // levels = 6 is the most: L0..L4 and the strands
    const auto counts = hairs_per_cluster(a);
    for (size_t l = 1; l < a.thick_levels.size(); ++l) {
        const ThickHairLevel &coarse = a.thick_levels[l - 1], &fine = a.thick_levels[l];
        // Sec. 5.1 step 2: each level about 4x smaller in cross-section area (>= 3 on the sampled
        // control points that decide the split; the mean over every control point is a little lower).
        const double ratio = coarse.mean_area / fine.mean_area;
        RecordProperty("area_ratio_L" + std::to_string(l), std::to_string(ratio));
        EXPECT_GT(ratio, 2.5) << "level " << l;
        EXPECT_LT(ratio, 8.0) << "level " << l;
        for (size_t c = 0; c < a.cluster_count(); ++c) EXPECT_GE(counts[l][c], counts[l - 1][c]);
        // Splits keep at least 4 strands per child on average.
        for (size_t h = 0; h < coarse.hair_count(); ++h) {
            int children = 0;
            for (size_t f = 0; f < fine.hair_count(); ++f) children += fine.parent[f] == static_cast<int32_t>(h) ? 1 : 0;
            ASSERT_GE(children, 1);
            if (children > 1) {
                EXPECT_GE(coarse.n_total(h), 4 * children) << "level " << l << " hair " << h;
            }
        }
    }
}

TEST(LodAssetLevels, LargeClustersShrinkFourfoldPerLevel) {
    // One guide: a single L0 cluster of 4000 strands, split per level into as many children as bring
    // the area about 4x down (a few: 4000 strands allow far more). The whole head is far from convex,
    // so its ellipse is relatively larger than its parts': the area shrinks more than the count.
    const LodAsset a = build_lod(testing::wavy_hair(4000, 8, 9), {.guides = 1, .levels = 4, .control_points = 6});
    ASSERT_EQ(a.thick_levels.size(), 3u);
    EXPECT_EQ(a.thick_levels[0].hair_count(), 1u);
    EXPECT_GE(a.thick_levels[1].hair_count(), 3u);
    EXPECT_LE(a.thick_levels[1].hair_count(), 8u);
    EXPECT_GE(a.thick_levels[2].hair_count(), 3 * a.thick_levels[1].hair_count());
    EXPECT_LE(a.thick_levels[2].hair_count(), 8 * a.thick_levels[1].hair_count());
    for (size_t l = 1; l < a.thick_levels.size(); ++l) {
        const double ratio = a.thick_levels[l - 1].mean_area / a.thick_levels[l].mean_area;
        RecordProperty("area_ratio_L" + std::to_string(l), std::to_string(ratio));
        EXPECT_GT(ratio, 2.5) << "level " << l;
        EXPECT_LT(ratio, 8.0) << "level " << l;
    }
}

TEST(LodAssetLevels, WithLevelsComposesParentsThroughDroppedLevels) {
    const LodAsset a = build_lod(testing::wavy_hair(4000, 8, 9), {.guides = 1, .levels = 4, .control_points = 6});
    ASSERT_GE(a.thick_levels.size(), 3u);
    const std::vector<size_t> kept_positions{0, 2};
    const LodAsset kept = a.with_levels(kept_positions);
    ASSERT_EQ(kept.thick_levels.size(), 2u);
    for (int32_t parent : kept.thick_levels[0].parent) EXPECT_EQ(parent, -1);
    const auto& fine = a.thick_levels[2];
    for (size_t h = 0; h < fine.hair_count(); ++h)
        EXPECT_EQ(kept.thick_levels[1].parent[h], a.thick_levels[1].parent[static_cast<size_t>(fine.parent[h])]);
    EXPECT_EQ(kept.thick_levels[1].member_first, fine.member_first);
    EXPECT_NO_THROW(kept.validate());
    // Without L0 the clusters still hold their own strands: the strands skin as in the full asset
    // (a cluster's strands were once read as the first kept level's hair ranges).
    const LodAsset without_l0 = build_lod(testing::wavy_hair(4000, 8, 9), {.guides = 24, .levels = 4, .control_points = 6})
                                    .with_levels(std::vector<size_t>{1, 2});
    const LodAsset full = build_lod(testing::wavy_hair(4000, 8, 9), {.guides = 24, .levels = 4, .control_points = 6});
    const std::vector<glm::vec3> turned = [&] {
        std::vector<glm::vec3> guides = full.rest_guides;
        for (glm::vec3& p : guides) p = glm::vec3(-p.y, p.x, p.z + 0.5f);
        return guides;
    }();
    EXPECT_EQ(without_l0.skin(turned).strands.points, full.skin(turned).strands.points);
    EXPECT_EQ(without_l0.rest_geometry().strands.points, full.rest_geometry().strands.points);
    EXPECT_THROW(a.with_levels(std::vector<size_t>{}), Error);
    EXPECT_THROW(a.with_levels(std::vector<size_t>{2, 0}), Error);
    EXPECT_THROW(a.with_levels(std::vector<size_t>{0, a.thick_levels.size()}), Error);
}

TEST(LodAssetLevels, LevelsStopWhereAreaStopsShrinking) {
    // A single strand has nothing to split: L0 alone.
    const LodAsset one = build_lod(testing::wavy_hair(1, 5, 2), {.guides = 4, .levels = 6});
    EXPECT_EQ(one.thick_levels.size(), 1u);
    // Seven strands cannot make two children of 4 strands on average.
    EXPECT_EQ(build_lod(testing::wavy_hair(7, 5, 2), {.guides = 1, .levels = 6}).thick_levels.size(), 1u);
    // Twelve strands in one cluster: a split makes at most 3 children (4 strands each on average);
    // k-means may leave them uneven and split the largest again, but never down to single strands.
    const LodAsset twelve = build_lod(testing::wavy_hair(12, 5, 2), {.guides = 1, .levels = 6});
    ASSERT_GE(twelve.thick_levels.size(), 2u);
    EXPECT_LE(twelve.thick_levels[1].hair_count(), 3u);
    EXPECT_LE(twelve.thick_levels.back().hair_count(), 6u);
    for (size_t l = 1; l < twelve.thick_levels.size(); ++l)
        EXPECT_GT(twelve.thick_levels[l].hair_count(), twelve.thick_levels[l - 1].hair_count());
    // 4000 strands in one cluster with levels = 3: the option still caps the depth.
    EXPECT_EQ(build_lod(testing::wavy_hair(4000, 6, 9), {.guides = 1, .levels = 3, .control_points = 6}).thick_levels.size(), 2u);
}

TEST(LodAssetLevels, AutomaticGuideCountFollowsTheStrands) {
    EXPECT_EQ(auto_guide_count(1), 1);
    EXPECT_EQ(auto_guide_count(10), 10);
    EXPECT_EQ(auto_guide_count(100), kMinAutoGuides);
    EXPECT_EQ(auto_guide_count(8000), 8000 / kStrandsPerGuide);
    EXPECT_EQ(auto_guide_count(100000), kMaxAutoGuides);
    EXPECT_EQ(auto_guide_count(size_t{1} << 40), kMaxAutoGuides);
    const StrandSet hair = testing::wavy_hair(3000, 6, 5);
    EXPECT_EQ(build_lod(hair, {.guides = 0, .levels = 3, .control_points = 6}).guide_count(),
              static_cast<size_t>(auto_guide_count(3000)));
    EXPECT_EQ(build_lod(hair, {.guides = 7, .levels = 3, .control_points = 6}).guide_count(), 7u);
}

TEST(LodAssetLevels, ProgressCountsEveryStepAndCancels) {
    LodBuildProgress progress;
    const LodAsset a = build_lod(testing::wavy_hair(500, 8, 4), {.guides = 8, .levels = 4, .control_points = 6, .progress = &progress});
    EXPECT_EQ(progress.total.load(), 4 + 2 + 3);
    EXPECT_EQ(progress.done.load(), progress.total.load());
    LodBuildProgress cancelled;
    cancelled.cancel = true;
    EXPECT_THROW(build_lod(testing::wavy_hair(500, 8, 4), {.guides = 8, .progress = &cancelled}), LodBuildCancelled);
}

TEST_F(LodAssetTest, RestPoseAndRigidMotionsSkinExactly) {
    const LodAsset& a = *asset_;
    const StrandSet resampled = lod_resampled(*strands_, 8);
    const LodGeometry rest = a.rest_geometry();
    EXPECT_LT(max_relative_error(rest.strands.points, resampled.points), 1e-5f);
    // Every point within the stated bound: half its cluster box's step, plus float rounding.
    const std::vector<int32_t> strand_clusters = a.strand_hairs(0);
    for (size_t s = 0; s < 3000; ++s)
        for (size_t k = 0; k < 8; ++k) {
            const QuantisationBox& box = a.offset_boxes[static_cast<size_t>(strand_clusters[s]) * 8 + k];
            ASSERT_LE(glm::distance(rest.strands.points[s * 8 + k], resampled.points[s * 8 + k]),
                      0.5f * glm::length(box.step) + 4e-7f * glm::length(resampled.points[s * 8 + k]));
        }
    // Radii are stored rounded up, by at most 2^-10 of their value.
    for (size_t i = 0; i < resampled.radius.size(); ++i) {
        ASSERT_GE(rest.strands.radius[i], resampled.radius[i]);
        ASSERT_LE(rest.strands.radius[i], resampled.radius[i] * (1.0f + std::exp2(-10.0f)));
    }

    const glm::mat4 motion = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, -2.0f, 3.0f)), 0.7f,
                                         glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)));
    auto move = [&](std::vector<glm::vec3> points) {
        for (glm::vec3& p : points) p = glm::vec3(motion * glm::vec4(p, 1.0f));
        return points;
    };
    const LodGeometry moved = a.skin(move(a.rest_guides));
    EXPECT_LT(max_relative_error(moved.strands.points, move(resampled.points)), 1e-5f);
    for (size_t l = 0; l < a.thick_levels.size(); ++l) {
        EXPECT_LT(max_relative_error(moved.levels[l].centre, move(rest.levels[l].centre)), 1e-5f) << "level " << l;
        for (size_t i = 0; i < moved.levels[l].major.size(); ++i) {
            const glm::vec3 expected = glm::mat3(motion) * rest.levels[l].major[i];
            ASSERT_LT(glm::distance(moved.levels[l].major[i], expected), 1e-4f * glm::length(expected) + 1e-7f);
        }
    }
}

TEST_F(LodAssetTest, DensityAndCornersFollowTheDecodedSections) {
    const LodAsset& a = *asset_;
    const LodGeometry rest = a.rest_geometry();
    for (size_t l = 0; l < a.thick_levels.size(); ++l) {
        const ThickHairLevel& level = a.thick_levels[l];
        const std::vector<float> density = a.density(l);
        for (size_t h = 0; h < level.hair_count(); ++h)
            for (size_t k = 0; k < 8; ++k) {
                const size_t at = h * 8 + k;
                const RestSection section = a.section(l, h, k);
                // Every test strand has radius 0.002 (stored rounded up to a half).
                const float radius = rest.strands.radius[0];
                ASSERT_NEAR(density[at], level.n_total(h) * radius * radius / (section.radii.x * section.radii.y), 1e-5f * density[at]);
                ASSERT_NEAR(glm::length(rest.levels[l].major[at]), section.radii.x, 1e-5f * section.radii.x);
                ASSERT_LT(std::abs(glm::dot(section.major_axis, section.minor_axis)), 1e-4f);
                const std::array<glm::vec3, 4>& corners = rest.levels[l].corners[at];
                ASSERT_LT(glm::distance(corners[0], rest.levels[l].centre[at] + rest.levels[l].major[at]), 1e-5f);
                ASSERT_LT(glm::distance(corners[3], rest.levels[l].centre[at] - rest.levels[l].minor[at]), 1e-5f);
            }
    }
}

TEST_F(LodAssetTest, DeterministicForASeedAndAnyThreadCount) {
    LodAsset single;
    {
        tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
        single = build_lod(*strands_, {.guides = 24, .levels = 6, .control_points = 8, .seed = 3});
    }
    EXPECT_EQ(single.guide_strands, asset_->guide_strands);
    ASSERT_EQ(single.thick_levels.size(), asset_->thick_levels.size());
    for (size_t l = 0; l < single.thick_levels.size(); ++l)
        EXPECT_EQ(single.strand_hairs(l), asset_->strand_hairs(l));
    EXPECT_EQ(single.strand_order, asset_->strand_order);
    const LodAsset other = build_lod(*strands_, {.guides = 24, .levels = 6, .control_points = 8, .seed = 4});
    EXPECT_NE(other.guide_strands, asset_->guide_strands);
}

TEST(LodAssetHardCases, OneStrandAndFewerStrandsThanGuides) {
    const LodAsset one = build_lod(testing::wavy_hair(1, 5, 2), {.guides = 256});
    EXPECT_EQ(one.guide_count(), 1u);
    EXPECT_EQ(one.cluster_count(), 1u);
    EXPECT_EQ(one.thick_levels[0].n_total(0), 1);
    const LodAsset few = build_lod(testing::wavy_hair(10, 5, 2), {.guides = 256});
    EXPECT_EQ(few.guide_count(), 10u);
    EXPECT_LT(max_relative_error(few.rest_geometry().strands.points,
                                 lod_resampled(testing::wavy_hair(10, 5, 2), 16).points),
              1e-5f);
}

TEST(LodAssetHardCases, IdenticalStrands) {
    StrandSet strands;
    const StrandSet one = testing::wavy_hair(1, 6, 5);
    for (int i = 0; i < 50; ++i) strands.add_curve(one.curve_points(0), one.radius);
    const LodAsset asset = build_lod(strands, {.guides = 8});
    EXPECT_EQ(asset.guide_count(), 1u);
    EXPECT_EQ(asset.thick_levels[0].n_total(0), 50);
    for (const glm::vec3& p : asset.rest_geometry().strands.points) EXPECT_TRUE(std::isfinite(p.x));
}

TEST(LodAssetHardCases, TwoPointAndCollinearStrands) {
    StrandSet strands;
    for (int i = 0; i < 40; ++i) {
        const std::vector<glm::vec3> line{{0.01f * i, 0, 0}, {0.01f * i, 0, -1}};  // all in one plane
        strands.add_curve(line);
    }
    const LodAsset asset = build_lod(strands, {.guides = 5, .levels = 3, .control_points = 4});
    const LodGeometry rest = asset.rest_geometry();
    EXPECT_LT(max_relative_error(rest.strands.points, lod_resampled(strands, 4).points), 1e-5f);
    for (const ThickHairLevel& level : asset.thick_levels) EXPECT_GE(level.coverage, 0.95);
}

TEST(LodAssetHardCases, HugeCoordinates) {
    const StrandSet strands = testing::wavy_hair(300, 8, 6, glm::vec3(1e6f, -1e6f, 1e6f));
    const LodAsset asset = build_lod(strands, {.guides = 8, .control_points = 6});
    const LodGeometry rest = asset.rest_geometry();
    EXPECT_LT(max_relative_error(rest.strands.points, lod_resampled(strands, 6).points), 1e-5f);
    for (size_t l = 0; l < asset.thick_levels.size(); ++l)
        for (size_t h = 0; h < asset.thick_levels[l].hair_count(); ++h)
            for (size_t k = 0; k < 6; ++k) {
                const glm::vec2 r = asset.section(l, h, k).radii;
                ASSERT_TRUE(std::isfinite(r.x) && std::isfinite(r.y) && r.x > 0.0f && r.y > 0.0f);
            }
}

TEST(LodAssetHardCases, ClearErrors) {
    StrandSet nan_strands = testing::wavy_hair(5, 4, 1);
    nan_strands.points[6].y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(build_lod(nan_strands), Error);
    EXPECT_THROW(build_lod(StrandSet{}), Error);
    EXPECT_THROW(build_lod(testing::wavy_hair(5, 4, 1), {.guides = -1}), Error);
    EXPECT_THROW(build_lod(testing::wavy_hair(5, 4, 1), {.levels = 1}), Error);
    const LodAsset asset = build_lod(testing::wavy_hair(5, 4, 1), {.guides = 2});
    EXPECT_THROW(asset.skin(std::vector<glm::vec3>(3)), Error);
    std::vector<glm::vec3> guides = asset.rest_guides;
    guides[0].x = std::numeric_limits<float>::infinity();
    EXPECT_THROW(asset.skin(guides), Error);
}

// A radius that is the same along every strand is stored once per strand (2 bytes a strand, not
// 2 n_c), and decodes to exactly what the per-point codes did; one tapered strand keeps every point's.
TEST(LodAssetStorage, StrandRadiusOncePerStrandWhenConstantAlongEach) {
    StrandSet constant = testing::wavy_hair(300, 10, 5);
    for (size_t s = 0; s < constant.curve_count(); ++s)
        for (auto i = constant.offsets[s]; i < constant.offsets[s + 1]; ++i) constant.radius[static_cast<size_t>(i)] = 0.001f * (1 + s % 7);
    StrandSet tapered = constant;
    tapered.radius[static_cast<size_t>(tapered.offsets[1]) - 1] *= 0.5f;  // the first strand's tip
    const LodOptions options{.guides = 8, .control_points = 8};
    const LodAsset per_strand = build_lod(constant, options), per_point = build_lod(tapered, options);
    ASSERT_EQ(per_strand.strand_radius.size(), 300u);
    ASSERT_EQ(per_point.strand_radius.size(), 300u * 8u);
    EXPECT_EQ(per_point.memory_bytes() - per_strand.memory_bytes(), 300u * 7u * sizeof(uint16_t));
    const StrandSet a = per_strand.rest_geometry().strands, b = per_point.rest_geometry().strands;
    for (size_t s = 1; s < 300; ++s)  // strand 0 differs at its tip
        for (size_t k = 0; k < 8; ++k) {
            ASSERT_EQ(a.radius[s * 8 + k], b.radius[s * 8 + k]) << s << " " << k;
            const float radius = 0.001f * (1 + s % 7);  // a half rounded up: at most 2^-10 above
            EXPECT_GE(a.radius[s * 8 + k], radius) << s;
            EXPECT_LE(a.radius[s * 8 + k], radius * (1.0f + 0x1p-10f)) << s;
        }
    EXPECT_NO_THROW(per_strand.validate());
    LodAsset damaged = per_strand;
    damaged.strand_radius.push_back(damaged.strand_radius.back());
    EXPECT_THROW(damaged.validate(), Error);
}

// A damaged stored asset is refused by validate() (run by from_arrays) instead of skinning to NaN.
TEST(LodAssetHardCases, ValidateRefusesValuesThatDecodeToNonFinite) {
    const LodAsset built = build_lod(testing::wavy_hair(200, 6, 4), {.guides = 4});
    EXPECT_NO_THROW(built.validate());
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::vector<std::function<void(LodAsset&)>> damages = {
        [&](LodAsset& a) { a.offset_boxes[0].lower.y = nan; },
        [&](LodAsset& a) { a.offset_boxes[0].step.z = inf; },
        [&](LodAsset& a) { a.offset_boxes[0].step.x = -1.0f; },
        [&](LodAsset& a) { a.offset_boxes[0].step.x = 1e35f; },  // the far corner overflows
        [&](LodAsset& a) { a.rest_guides[1].x = nan; },
        [&](LodAsset& a) { a.strand_radius[0] = 0x7c00; },         // half +inf
        [&](LodAsset& a) { a.strand_radius[0] = 0x8001; },         // negative
        [&](LodAsset& a) { a.thick_levels[0].radii[0].y = 0x7e00; },  // half NaN
        [&](LodAsset& a) { a.radius_exponent = 200; },             // every radius overflows float
    };
    for (size_t i = 0; i < damages.size(); ++i) {
        LodAsset damaged = built;
        damages[i](damaged);
        EXPECT_THROW(damaged.validate(), Error) << "damage " << i;
    }
}

}  // namespace
}  // namespace hairlod
