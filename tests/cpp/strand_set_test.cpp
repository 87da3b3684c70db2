#include "hairlod/core/strand_set.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

StrandSet two_curves() {
    const std::vector<glm::vec3> points{{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {1, 0, 1}, {1, 0, 2}};
    const std::vector<int64_t> counts{2, 3};
    return strands_from_counts(points, counts, std::vector<float>(5, 0.1f));
}

std::string validation_message(const StrandSet& strands) {
    try {
        strands.validate();
    } catch (const Error& error) {
        return error.what();
    }
    return "";
}

TEST(StrandSet, FromCountsBuildsOffsets) {
    const StrandSet strands = two_curves();
    EXPECT_EQ(strands.curve_count(), 2u);
    EXPECT_EQ(strands.point_count(), 5u);
    EXPECT_EQ(strands.offsets, (std::vector<int64_t>{0, 2, 5}));
    EXPECT_EQ(strands.curve_size(1), 3u);
    EXPECT_EQ(strands.curve_points(1)[2], glm::vec3(1, 0, 2));
}

TEST(StrandSet, EmptySetIsValid) {
    StrandSet strands;
    EXPECT_EQ(strands.curve_count(), 0u);
    EXPECT_NO_THROW(strands.validate());
}

TEST(StrandSet, AddCurveAppends) {
    StrandSet strands;
    const std::vector<glm::vec3> curve{{0, 0, 0}, {1, 1, 1}};
    strands.add_curve(curve);
    strands.add_curve(curve, std::vector<float>{0.5f, 0.25f});
    EXPECT_EQ(strands.offsets, (std::vector<int64_t>{0, 2, 4}));
    EXPECT_EQ(strands.radius, (std::vector<float>{0, 0, 0.5f, 0.25f}));
    EXPECT_THROW(strands.add_curve(curve, std::vector<float>{1.0f}), Error);
}

TEST(StrandSet, RejectsNonFinitePoints) {
    StrandSet strands = two_curves();
    strands.points[3].y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(validation_message(strands), "point 3 is not finite (NaN or Inf)");
    strands.points[3].y = std::numeric_limits<float>::infinity();
    EXPECT_NE(validation_message(strands).find("point 3"), std::string::npos);
}

StrandSet scaled(const StrandSet& strands, float scale) {
    StrandSet result = strands;
    for (glm::vec3& p : result.points) p *= scale;
    for (float& r : result.radius) r *= scale;
    return result;
}

std::string range_message(const StrandSet& strands) {
    try {
        strands.require_float_range("lod");
    } catch (const Error& error) {
        return error.what();
    }
    return "";
}

TEST(StrandSet, FloatRangeAcceptsEveryScaleFloat32GeometryHandles) {
    for (float scale : {1e-9f, 1e-6f, 1.0f, 1e6f, 1e12f}) EXPECT_EQ(range_message(scaled(two_curves(), scale)), "") << scale;
    // Coincident points (extent 0) are degenerate geometry the algorithms handle, not a scale problem.
    EXPECT_EQ(range_message(scaled(two_curves(), 0.0f)), "");
    EXPECT_EQ(range_message(StrandSet{}), "");
}

TEST(StrandSet, FloatRangeRefusesHugeAndTinyHair) {
    const std::string huge = range_message(scaled(two_curves(), 1e30f));
    EXPECT_EQ(huge.rfind("lod: coordinates or radii reach 2e+30", 0), 0u) << huge;
    EXPECT_NE(huge.find("scale the hair down"), std::string::npos);
    StrandSet thick = two_curves();
    thick.radius[0] = 1e20f;
    EXPECT_NE(range_message(thick).find("reach 1e+20"), std::string::npos);
    const std::string tiny = range_message(scaled(two_curves(), 1e-30f));
    EXPECT_NE(tiny.find("lod: the hair is 2.24e-30 across"), std::string::npos) << tiny;
    EXPECT_NE(tiny.find("scale the hair up"), std::string::npos);
}

TEST(StrandSet, RejectsOffsetsNotStrictlyIncreasing) {
    StrandSet strands = two_curves();
    strands.offsets = {0, 2, 2, 5};
    EXPECT_NE(validation_message(strands).find("strictly increasing"), std::string::npos);
    strands.offsets = {1, 5};
    EXPECT_EQ(validation_message(strands), "offsets must start with 0");
    strands.offsets = {0, 2, 4};
    EXPECT_NE(validation_message(strands).find("offsets end at 4 but there are 5 points"), std::string::npos);
}

TEST(StrandSet, RejectsSinglePointCurves) {
    StrandSet strands = two_curves();
    strands.offsets = {0, 1, 5};
    EXPECT_EQ(validation_message(strands), "curve 0 has 1 point; every curve needs at least 2");
}

TEST(StrandSet, RejectsNegativeOrMissingRadius) {
    StrandSet strands = two_curves();
    strands.radius[4] = -0.5f;
    EXPECT_NE(validation_message(strands).find("radius[4] is negative"), std::string::npos);
    strands.radius.pop_back();
    EXPECT_NE(validation_message(strands).find("radius has 4 values for 5 points"), std::string::npos);
}

TEST(StrandSet, AttributesAreSizedByDomain) {
    StrandSet strands = two_curves();
    strands.set_attribute("color", AttributeDomain::Point, 3, std::vector<float>(15, 1.0f));
    strands.set_attribute("id", AttributeDomain::Curve, 1, {7.0f, 8.0f});
    ASSERT_NE(strands.find_attribute("color"), nullptr);
    EXPECT_EQ(strands.find_attribute("id")->values[1], 8.0f);
    EXPECT_EQ(strands.find_attribute("missing"), nullptr);
    EXPECT_THROW(strands.set_attribute("bad", AttributeDomain::Curve, 1, {1.0f}), Error);
    EXPECT_THROW(strands.set_attribute("", AttributeDomain::Curve, 1, {1.0f, 2.0f}), Error);
    EXPECT_NO_THROW(strands.validate());
}

}  // namespace
}  // namespace hairlod
