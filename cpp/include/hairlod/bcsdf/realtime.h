#pragma once
// The real-time tier of realtime-pbr-hair-thesis.txt Sec. 4.3 (Karis 2016 and Tafuri 2019
// approximations of Marschner's N_R, N_TT, N_TRT): S = sum_p M_p(theta_h) N_p / cos^2(theta_d)
// (thesis Eq. 4.1-4.3), with the longitudinal lobes of Marschner (thesis Table 2.2).
//
// Absorption from colour (thesis Eq. 4.17-4.19): T_TT = C^(sqrt(1 - h^2 a^2) / (2 cos theta_d)). We
// take the colour C = exp(-4 sigma_a), so that at h = 0 this equals the physical exp(-2 sigma_a / cos).
#include "hairlod/bcsdf/bcsdf.h"

namespace hairlod::bcsdf {

enum class RealtimeTT {
    Tafuri,  // A_TT at h = 0 (thesis Eq. 4.19-4.22)
    Karis,   // A_TT at Karis' fitted offset h_TT (thesis Eq. 4.16, 4.18)
};

class RealtimeBcsdf final : public FiberBcsdf {
public:
    explicit RealtimeBcsdf(const HairParams& params, RealtimeTT tt = RealtimeTT::Tafuri);

    LobeValues eval_lobes(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    std::span<const LongitudinalLobe> lobe_shapes() const override { return lobes_; }
    std::string_view name() const override { return "realtime"; }

private:
    HairParams params_;
    RealtimeTT tt_;
    std::array<LongitudinalLobe, 3> lobes_;
    glm::dvec3 log_color_;  // log C = -4 sigma_a
    double trt_scale_;      // Tafuri's s_r (thesis Eq. 4.27)
};

}  // namespace hairlod::bcsdf
