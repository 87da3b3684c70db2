#pragma once
// Choosing a single-fibre model by name, with the options each model has.
#include <memory>
#include <string_view>

#include "hairlod/bcsdf/aggregated.h"
#include "hairlod/bcsdf/bcsdf.h"
#include "hairlod/bcsdf/huang.h"
#include "hairlod/bcsdf/marschner.h"
#include "hairlod/bcsdf/realtime.h"

namespace hairlod::bcsdf {

enum class BcsdfModel { Chiang, Huang, Marschner, MarschnerCircularGaussian, FiberRtd, Realtime, Aggregated };

// Parses "chiang", "huang", "marschner", "marschner_cg" (its circular Gaussian tier), "fiber_rtd", "realtime",
// "aggregated"; throws Error naming the model otherwise.
BcsdfModel parse_bcsdf_model(std::string_view name);

struct ModelOptions {
    MarschnerCaustic marschner_caustic{};
    RealtimeTT realtime_tt = RealtimeTT::Tafuri;
    ClusterState cluster{};
    AggregatedFibre aggregated_fibre = AggregatedFibre::Rtd;
    int huang_residual_samples = HuangBcsdf::kDefaultResidualSamples;
};

// A model over validated parameters (throws Error naming the bad parameter).
std::unique_ptr<FiberBcsdf> make_bcsdf(BcsdfModel model, const HairParams& params, const ModelOptions& options = {});

}  // namespace hairlod::bcsdf
