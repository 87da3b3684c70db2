#include "hairlod/bcsdf/bcsdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bcsdf_test_util.h"
#include "hairlod/bcsdf/aggregated.h"
#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/model_factory.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {
namespace {

TEST(Bcsdf, ParseAndFactory) {
    for (const char* name : {"chiang", "marschner", "marschner_cg", "fiber_rtd", "realtime", "aggregated"})
        EXPECT_EQ(make_bcsdf(parse_bcsdf_model(name), HairParams{})->name(), name);
    try {
        parse_bcsdf_model("kajiya");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("kajiya"), std::string::npos);
    }
    HairParams bad;
    bad.eta = 1.0;
    EXPECT_THROW(make_bcsdf(BcsdfModel::Realtime, bad), Error);
}

TEST(Bcsdf, BatchMatchesSingleEvaluation) {
    const auto bcsdf = make_bcsdf(BcsdfModel::Marschner, HairParams{});
    std::mt19937_64 rng(17);
    std::vector<glm::vec3> wi(1000), wo(1000), out(1000);
    for (size_t k = 0; k < wi.size(); ++k) {
        wi[k] = glm::vec3(test::random_direction(rng));
        wo[k] = glm::vec3(test::random_direction(rng));
    }
    evaluate(*bcsdf, wi, wo, out);
    for (size_t k = 0; k < wi.size(); k += 37) {
        const glm::dvec3 single = bcsdf->eval(glm::dvec3(wi[k]), glm::dvec3(wo[k]));
        EXPECT_NEAR(out[k].y, single.y, 1e-6 * std::max(1.0, single.y));
    }
    std::vector<glm::vec3> short_out(10);
    EXPECT_THROW(evaluate(*bcsdf, wi, wo, short_out), Error);
}

// Random parameters over the hard ranges: beta log-uniform in [1e-3, 1], sigma_a in [0, 50], eta
// in (1, 2.5] (eta' crosses 2), eccentricity in [0.75, 1.3], cuticle tilt up to 0.3 rad.
HairParams random_params(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    HairParams p;
    p.eta = 1.0 + 1e-3 + 1.5 * u(rng);
    p.sigma_a = {50.0 * u(rng) * u(rng), 50.0 * u(rng), u(rng) < 0.2 ? 0.0 : 50.0 * u(rng)};
    p.beta_m = std::pow(10.0, -3.0 * u(rng));
    p.beta_n = std::pow(10.0, -3.0 * u(rng));
    p.alpha = 0.3 * (2.0 * u(rng) - 1.0);
    p.coat = u(rng);
    p.eccentricity = 0.75 + 0.55 * u(rng);
    return p;
}

// At least 10^6 random evaluations over all models plus the corners: finite and non-negative.
TEST(Bcsdf, HardCasesAreFiniteAndNonNegative) {
    std::mt19937_64 rng(2024);
    const std::vector<glm::dvec3> corners = test::corner_directions();
    struct Budget {
        BcsdfModel model;
        int parameter_sets;
        int pairs;
    };
    size_t evaluations = 0;
    // Budgets follow the cost per evaluation; the far-field Chiang model (up to 4096 Gauss-Legendre nodes
    // per value) gets random pairs and the corners paired diagonally instead of all corner pairs.
    for (const Budget& budget : {Budget{BcsdfModel::Realtime, 400, 1000}, Budget{BcsdfModel::Marschner, 60, 1000},
                                 Budget{BcsdfModel::MarschnerCircularGaussian, 10, 1000},
                                 Budget{BcsdfModel::FiberRtd, 40, 1000}, Budget{BcsdfModel::Chiang, 3, 100}}) {
        for (int set = 0; set < budget.parameter_sets; ++set) {
            const HairParams params = random_params(rng);
            const auto bcsdf = make_bcsdf(budget.model, params);
            std::vector<glm::vec3> wi, wo;
            for (int k = 0; k < budget.pairs; ++k) {
                wi.push_back(glm::vec3(test::random_direction(rng)));
                wo.push_back(glm::vec3(test::random_direction(rng)));
            }
            const size_t stride = budget.model == BcsdfModel::Chiang ? corners.size() : 1;
            for (size_t a = 0; a < corners.size(); ++a)
                for (size_t b = a % stride; b < corners.size(); b += stride) {
                    wi.push_back(glm::vec3(corners[a]));
                    wo.push_back(glm::vec3(corners[b]));
                }
            std::vector<glm::vec3> out(wi.size());
            evaluate(*bcsdf, wi, wo, out);
            evaluations += out.size();
            for (size_t k = 0; k < out.size(); ++k)
                ASSERT_TRUE(test::finite_non_negative(glm::dvec3(out[k])))
                    << bcsdf->name() << " eta " << params.eta << " beta_m " << params.beta_m << " beta_n "
                    << params.beta_n << " wi " << wi[k].x << "," << wi[k].y << "," << wi[k].z << " wo " << wo[k].x
                    << "," << wo[k].y << "," << wo[k].z;
        }
    }
    // The aggregated model: n from 1 to 10^4, rho from 1e-4 to 1 (one table per parameter set).
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int set = 0; set < 12; ++set) {
        const HairParams params = random_params(rng);
        const auto table = std::make_shared<const AggregatedTable>(aggregated_table(FiberRtdBcsdf(params), 9));
        for (const ClusterState cluster : {ClusterState{1.0, 1e-4}, ClusterState{1e4, 1.0},
                                           ClusterState{std::pow(10.0, 4.0 * unit(rng)), std::pow(10.0, -4.0 * unit(rng))}}) {
            const AggregatedBcsdf bcsdf(params, cluster, table);
            std::vector<glm::vec3> wi, wo;
            for (int k = 0; k < 2000; ++k) {
                wi.push_back(glm::vec3(test::random_direction(rng)));
                wo.push_back(glm::vec3(test::random_direction(rng)));
            }
            for (const glm::dvec3& a : corners)
                for (const glm::dvec3& b : corners) {
                    wi.push_back(glm::vec3(a));
                    wo.push_back(glm::vec3(b));
                }
            std::vector<glm::vec3> out(wi.size());
            evaluate(bcsdf, wi, wo, out);
            evaluations += out.size();
            for (const glm::vec3& v : out) ASSERT_TRUE(test::finite_non_negative(glm::dvec3(v))) << cluster.hair_count;
        }
    }
    // The near field of the Chiang model, with h -> +-1.
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int set = 0; set < 200; ++set) {
        const ChiangBcsdf bcsdf(random_params(rng));
        std::vector<glm::vec3> wi, wo, out;
        std::vector<float> h;
        for (int k = 0; k < 1000; ++k) {
            wi.push_back(glm::vec3(test::random_direction(rng)));
            wo.push_back(glm::vec3(test::random_direction(rng)));
            h.push_back(k % 10 == 0 ? (k % 20 == 0 ? 1.0f : -1.0f) : float(u(rng)));
        }
        out.resize(wi.size());
        evaluate_near_field(bcsdf, wi, wo, h, out);
        evaluations += out.size();
        for (const glm::vec3& v : out) ASSERT_TRUE(test::finite_non_negative(glm::dvec3(v)));
    }
    RecordProperty("evaluations", std::to_string(evaluations));
    EXPECT_GE(evaluations, 1000000u);
}

}  // namespace
}  // namespace hairlod::bcsdf
