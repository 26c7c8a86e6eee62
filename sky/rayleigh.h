// Rayleigh single scattering: DoLP = Pmax·sin²γ/(1+cos²γ), E-vector ⟂ the scattering plane
// (E ∝ d × s). Radiance follows the Rayleigh phase function (1+cos²γ), scaled so the radiance
// 90° from the sun is 1 (relative units). Sun et al. 2019 eqs. 3–4; SkyPole eq. 1.
#pragma once

#include "sky/sky_model.h"

namespace skypol::sky {

struct RayleighParams {
  double max_dolp = 1.0;  // Pmax ∈ [0, 1]: the depolarization of real skies (≈ 0.7 on clear days)
};

class RayleighSky final : public SkyModel {
 public:
  explicit RayleighSky(RayleighParams params = {});
  std::string name() const override { return "rayleigh"; }
  Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const override;
  void stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const override;
  void stokes_soa(const ViewRaysSoA& rays, const Sun& sun, const StokesSoA& out) const override;
  const RayleighParams& params() const { return params_; }

 private:
  RayleighParams params_;
};

}  // namespace skypol::sky
