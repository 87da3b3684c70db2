#pragma once
// The Chiang fibre closest to a Huang et al. 2022 microfacet fibre: dual scattering, the aggregated
// and real-time BCSDFs and the bake are built on Chiang's lobes (longitudinal variance from beta_m,
// logistic azimuth from beta_n), so a Huang material reaches them as the Chiang fibre that scatters
// most like it. Absorption, index, tilt and lobe weights carry over; beta_m and beta_n are fitted.
#include "hairlod/bcsdf/hair_params.h"

namespace hairlod::bcsdf {

struct ChiangFit {
    HairParams params;            // the Huang fibre with beta_m, beta_n (and coat 0) set to the fit
    double relative_error = 0.0;  // ||S_chiang - S_huang|| / ||S_huang|| over the fit's directions
    double start_error = 0.0;     // the same for beta_m = beta_n = the microfacet roughness
};

// Fits beta_m to the longitudinal profile (S cos(theta_i) summed over azimuth) and then beta_n to
// the azimuthal profile (summed over theta_i) of the luminance of S cos(theta_i), over views at
// theta_o = -50, -20, 10 and 40 degrees, by golden-section search in [0.02, 1]. Deterministic; about
// 0.2 s on 2 cores.
ChiangFit fit_chiang_to_huang(const HairParams& huang);

}  // namespace hairlod::bcsdf
