#pragma once
// Dual scattering (Zinke et al. 2008, as summarised in circular-gaussian-hair-env-lighting.txt
// Sec. 4.3 and hair-lod-aggregated-bcsdf.txt Sec. 3.2): the fibre's average forward and backward
// attenuations, shifts and widths as functions of the inclination theta_d, and the local
// backscattering terms A_1, A_3, A_b, Delta_b, sigma_b, all computed from a single-fibre model by
// numerical integration.
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "hairlod/bcsdf/bcsdf.h"
#include "hairlod/bcsdf/quadrature.h"

namespace hairlod::bcsdf {

// Zinke et al. 2008's backscattering density d_b (Xu et al. 2011, Sec. 3: between 0.6 and 0.8).
inline constexpr double kDefaultBackscatterDensity = 0.7;

struct DualScatteringSample {
    double theta_d = 0.0;
    // Xu et al. 2011, Eq. 32-33: the energy a fibre seen at inclination theta_d scatters into the
    // forward (|phi| > pi/2) and backward (|phi| < pi/2) half spaces, integral of S cos(theta_i) dw_i.
    glm::dvec3 a_f{0.0}, a_b{0.0};
    // Attenuation-weighted mean shift alpha_p and width beta_p (theta_h convention, radians) of the lobes.
    glm::dvec3 alpha_f{0.0}, alpha_b{0.0};
    glm::dvec3 beta_f{0.0}, beta_b{0.0};
    // Zinke et al. 2008, Sec. 4 (local multiple scattering): backscattering terms.
    glm::dvec3 A_1{0.0}, A_3{0.0}, A_b{0.0};
    glm::dvec3 delta_b{0.0}, sigma_b{0.0};
};

// The terms at one inclination theta_d in [-pi/2, pi/2].
DualScatteringSample dual_scattering(const FiberBcsdf& bcsdf, double theta_d,
                                     double backscatter_density = kDefaultBackscatterDensity,
                                     const QuadratureTolerance& tolerance = {1e-6, 1e-5, 30});

// The terms at every inclination of `theta_d` (in parallel).
std::vector<DualScatteringSample> dual_scattering_table(const FiberBcsdf& bcsdf, std::span<const double> theta_d,
                                                        double backscatter_density = kDefaultBackscatterDensity,
                                                        const QuadratureTolerance& tolerance = {1e-6, 1e-5, 30});

// The backscattering terms from averaged a_f, a_b, alpha_f/b, beta_f/b (Zinke et al. 2008, Sec. 4);
// fills A_1, A_3, A_b, delta_b and sigma_b of `sample`.
void backscattering_terms(DualScatteringSample& sample, double backscatter_density);

}  // namespace hairlod::bcsdf
