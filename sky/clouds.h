// Partly cloudy skies as an optional, seeded effect on top of any clear-sky model. A cloud of
// opacity α ∈ [0, 1] in direction d mixes the clear sky with unpolarized cloud light:
//   S0' = S0·(1 − α + α·brightness),   (S1', S2', S3') = (1 − α)·(S1, S2, S3),
// so clouds raise the radiance, lower DoLP, and keep the AoLP wherever the cloud is thin
// (α < 1). That is the observed behaviour of thin cloud (Pomozi, Horváth & Wehner 2001: the
// E-vector pattern of the clear sky persists under it); thick cloud (α = 1) is unpolarized here.
// The opacity is a fractal value-noise field on the sky, fixed by the seed, static over a time
// series (no wind), calibrated so that a fraction `coverage` of all directions has α > ½.
// A scene without clouds never builds this wrapper, so it costs nothing there.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "sky/noise.h"
#include "sky/sky_model.h"

namespace skypol::sky {

struct CloudParams {
  double coverage = 0.0;      // fraction of the sky under cloud (α > ½), [0, 1]
  std::uint64_t seed = 0;     // the same seed gives the same clouds
  double scale_deg = 15.0;    // typical angular size of a cloud, [1, 90]
  double softness = 0.1;      // width of the thin edge, in units of the noise range, (0, 1]
  double brightness = 2.5;    // radiance of thick cloud relative to the clear sky behind it, ≥ 1
};

void validate(const CloudParams& params);  // throws std::invalid_argument naming the field

class CloudySky final : public SkyModel {
 public:
  CloudySky(std::unique_ptr<SkyModel> clear, CloudParams params);
  std::string name() const override { return clear_->name(); }
  Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const override;
  void stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const override;

  // Cloud opacity α ∈ [0, 1] in the unit ENU direction d.
  double opacity(const Eigen::Vector3d& d) const;
  const CloudParams& params() const { return params_; }
  const SkyModel& clear() const { return *clear_; }

 private:
  float fractal_noise_at(float x, float y, float z) const;
  float opacity_f(float x, float y, float z) const;

  std::unique_ptr<SkyModel> clear_;
  CloudParams params_;
  std::vector<detail::ValueNoise> octaves_;  // one seeded table per octave
  float frequency_ = 1;   // noise lattice cells per unit of direction
  float threshold_ = 0;   // noise value at α = ½
};

}  // namespace skypol::sky
