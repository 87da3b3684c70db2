#include "hairlod/core/strand_density.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

struct Hair {
    std::vector<glm::vec3> points;
    std::vector<int64_t> offsets{0};
    std::vector<float> radius;

    void add(const std::vector<glm::vec3>& strand, float r) {
        points.insert(points.end(), strand.begin(), strand.end());
        radius.insert(radius.end(), strand.size(), r);
        offsets.push_back(static_cast<int64_t>(points.size()));
    }
    StrandDensityOptions box(int resolution = 8) const {
        StrandDensityOptions options;
        options.lower = options.upper = glm::dvec3(points.front());
        for (const glm::vec3& p : points) {
            options.lower = glm::min(options.lower, glm::dvec3(p));
            options.upper = glm::max(options.upper, glm::dvec3(p));
        }
        options.resolution = resolution;
        return options;
    }
    // The projected area of every segment, sum of (r_i + r_{i+1}) l.
    double area() const {
        double sum = 0.0;
        for (size_t c = 0; c + 1 < offsets.size(); ++c)
            for (int64_t i = offsets[c]; i + 1 < offsets[c + 1]; ++i)
                sum += (double(radius[i]) + radius[i + 1]) * glm::length(glm::dvec3(points[i + 1]) - glm::dvec3(points[i]));
        return sum;
    }
};

double field_sum(const StrandDensity& density, int field) {
    const size_t cells = density.fields.size() / kStrandDensityFields;
    return std::accumulate(density.fields.begin() + field * cells, density.fields.begin() + (field + 1) * cells, 0.0);
}

Hair random_hair(int strands, int points_per_strand, unsigned seed) {
    std::mt19937 random(seed);
    std::normal_distribution<float> normal;
    Hair hair;
    for (int c = 0; c < strands; ++c) {
        std::vector<glm::vec3> strand;
        glm::vec3 p{normal(random), normal(random), normal(random)};
        for (int i = 0; i < points_per_strand; ++i) {
            strand.push_back(p);
            p += 0.3f * glm::vec3{normal(random), normal(random), normal(random)};
        }
        hair.add(strand, 0.001f + 0.0001f * static_cast<float>(c % 7));
    }
    return hair;
}

TEST(StrandDensity, HoldsEverySegmentsAreaWhereverItLies) {
    // Trilinear weights sum to one and the margin voxels take what the box's faces spread outwards:
    // the grid holds the strands' whole projected area, per unit volume.
    const Hair hair = random_hair(300, 9, 3);
    const StrandDensity density = strand_density(hair.points, hair.offsets, hair.radius, hair.box(12));
    ASSERT_EQ(density.strand_step, 1);
    const double volume = density.voxel * density.voxel * density.voxel;
    EXPECT_NEAR(field_sum(density, 0) * volume, hair.area(), 1e-9 * hair.area());
    // The tangent's squares sum to one: the three diagonal moments add up to the density.
    EXPECT_NEAR(field_sum(density, 1) + field_sum(density, 2) + field_sum(density, 3), field_sum(density, 0),
                1e-9 * field_sum(density, 0));
    for (double value : density.fields) EXPECT_TRUE(std::isfinite(value));
}

TEST(StrandDensity, StrandsAlongAnAxisHaveOnlyThatMoment) {
    Hair hair;
    for (int c = 0; c < 20; ++c) hair.add({{0, 0.1f * c, 0.05f * c}, {0.5f, 0.1f * c, 0.05f * c}, {2, 0.1f * c, 0.05f * c}}, 0.01f);
    const StrandDensity density = strand_density(hair.points, hair.offsets, hair.radius, hair.box(10));
    EXPECT_NEAR(field_sum(density, 1), field_sum(density, 0), 1e-12 * field_sum(density, 0));
    for (int field = 2; field < kStrandDensityFields; ++field) EXPECT_EQ(field_sum(density, field), 0.0) << field;
    // Voxels: 2 / 10 along x, the box's largest extent; one of margin on every side.
    EXPECT_DOUBLE_EQ(density.voxel, 0.2);
    EXPECT_EQ(density.shape, (std::array<int, 3>{12, 12, 7}));
}

TEST(StrandDensity, SegmentsAreSampledAlongTheirLength) {
    // One long segment through the middle of a row of voxels along x: samples at most half a voxel
    // apart put the same density in every inner voxel it crosses, not all of it where its ends are.
    Hair hair;
    hair.add({{0, 0, 0}, {4, 0, 0}}, 0.01f);
    hair.add({{0, 1, 1}, {0, 1, 1}}, 0.0f);  // a zero-length strand of no radius: the box's other corner
    const StrandDensity density = strand_density(hair.points, hair.offsets, hair.radius, hair.box(4));
    const auto at = [&](int i, int j, int k) {
        return density.fields[(static_cast<size_t>(i) * density.shape[1] + j) * density.shape[2] + k];
    };
    // Voxels of 1, centred at x = i - 0.5: 8 samples at x = 0.25, 0.75, ..., 3.75 give the inner voxels
    // i = 2, 3 two samples' worth each, i = 1, 4 1.75, the margins 0.25 (only the ends would leave 2 and 3
    // empty). The segment lies on the plane between the margin's centres (y, z = -0.5) and the first
    // row's (0.5), so it splits evenly between them.
    const double sample = at(2, 1, 1) / 2.0;
    EXPECT_GT(sample, 0.0);
    const double expected[6] = {0.25, 1.75, 2.0, 2.0, 1.75, 0.25};
    for (int i = 0; i < 6; ++i) {
        EXPECT_NEAR(at(i, 1, 1), expected[i] * sample, 1e-12 * sample) << i;
        EXPECT_NEAR(at(i, 0, 0), at(i, 1, 1), 1e-12 * sample) << i;
    }
}

TEST(StrandDensity, FewerStrandsStandForAll) {
    // Identical strands: every k-th standing for k holds the same density as all of them.
    Hair hair;
    for (int c = 0; c < 1000; ++c) hair.add({{0, 0, 0}, {0.3f, 0.4f, 0.1f}, {1, 1, 1}}, 0.002f);
    const StrandDensity all = strand_density(hair.points, hair.offsets, hair.radius, hair.box(6));
    StrandDensityOptions options = hair.box(6);
    options.max_samples = 600;  // 3000 points: every 5th strand by the points, then by the samples
    const StrandDensity fewer = strand_density(hair.points, hair.offsets, hair.radius, options);
    EXPECT_EQ(all.strand_step, 1);
    EXPECT_GT(fewer.strand_step, 5);
    EXPECT_EQ(1000 % fewer.strand_step, 0);  // the strands kept stand for all of them exactly
    ASSERT_EQ(fewer.fields.size(), all.fields.size());
    for (size_t i = 0; i < all.fields.size(); ++i) EXPECT_NEAR(fewer.fields[i], all.fields[i], 1e-9 * (1.0 + all.fields[i]));
}

TEST(StrandDensity, BadInputIsNamed) {
    Hair hair;
    hair.add({{0, 0, 0}, {1, 0, 0}}, 0.01f);
    const StrandDensityOptions options = hair.box();
    const auto message = [&](std::vector<int64_t> offsets, std::vector<float> radius, StrandDensityOptions o) {
        try {
            strand_density(hair.points, offsets, radius, o);
        } catch (const Error& error) {
            return std::string(error.what());
        }
        return std::string();
    };
    EXPECT_NE(message({0, 1}, hair.radius, options).find("offsets must run from 0 to 2"), std::string::npos);
    EXPECT_NE(message({0, 0, 2}, hair.radius, options).find("offsets must rise"), std::string::npos);
    EXPECT_NE(message(hair.offsets, {0.01f}, options).find("radius must have one value per point"), std::string::npos);
    StrandDensityOptions bad = options;
    bad.resolution = 0;
    EXPECT_NE(message(hair.offsets, hair.radius, bad).find("resolution and max_samples"), std::string::npos);
    bad = options;
    bad.sample_spacing = 0.0;
    EXPECT_NE(message(hair.offsets, hair.radius, bad).find("sample_spacing"), std::string::npos);
    Hair not_finite = hair;
    not_finite.points[1].y = std::nanf("");
    try {
        strand_density(not_finite.points, not_finite.offsets, not_finite.radius, options);
        ADD_FAILURE() << "a point that is not finite was splatted";
    } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find("must be finite"), std::string::npos);
    }
    not_finite = hair;
    not_finite.radius[0] = INFINITY;
    EXPECT_THROW(strand_density(not_finite.points, not_finite.offsets, not_finite.radius, options), Error);
    bad = options;
    bad.upper.x = std::nan("");
    EXPECT_NE(message(hair.offsets, hair.radius, bad).find("the box must be finite"), std::string::npos);
}

}  // namespace
}  // namespace hairlod
