#include "hairlod/bcsdf/model_factory.h"

#include <string>

#include "hairlod/bcsdf/chiang.h"
#include "hairlod/bcsdf/fiber_rtd.h"
#include "hairlod/bcsdf/srbf.h"
#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

BcsdfModel parse_bcsdf_model(std::string_view name) {
    if (name == "chiang") return BcsdfModel::Chiang;
    if (name == "huang") return BcsdfModel::Huang;
    if (name == "marschner") return BcsdfModel::Marschner;
    if (name == "marschner_cg") return BcsdfModel::MarschnerCircularGaussian;
    if (name == "fiber_rtd") return BcsdfModel::FiberRtd;
    if (name == "realtime") return BcsdfModel::Realtime;
    if (name == "aggregated") return BcsdfModel::Aggregated;
    throw Error("unknown BCSDF model '" + std::string(name) +
                "' (expected chiang, huang, marschner, marschner_cg, fiber_rtd, realtime or aggregated)");
}

std::unique_ptr<FiberBcsdf> make_bcsdf(BcsdfModel model, const HairParams& params, const ModelOptions& options) {
    switch (model) {
        case BcsdfModel::Chiang: return std::make_unique<ChiangBcsdf>(params);
        case BcsdfModel::Huang: return std::make_unique<HuangBcsdf>(params, options.huang_residual_samples);
        case BcsdfModel::Marschner: return std::make_unique<MarschnerBcsdf>(params, options.marschner_caustic);
        case BcsdfModel::MarschnerCircularGaussian:
            return std::make_unique<CircularGaussianMarschner>(MarschnerBcsdf(params, options.marschner_caustic),
                                                               default_circular_gaussian_tables());
        case BcsdfModel::FiberRtd: return std::make_unique<FiberRtdBcsdf>(params);
        case BcsdfModel::Realtime: return std::make_unique<RealtimeBcsdf>(params, options.realtime_tt);
        case BcsdfModel::Aggregated: return std::make_unique<AggregatedBcsdf>(params, options.cluster, nullptr, options.aggregated_fibre);
    }
    throw Error("unknown BCSDF model");
}

}  // namespace hairlod::bcsdf
