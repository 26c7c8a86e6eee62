// The sun's disc as unpolarized radiance, for scenes that need an over-exposed sun. Applied
// outermost: behind cloud (an inner CloudySky) the disc is dimmed by the cloud's transmission
// 1 − α, so thick cloud hides it while the cloud itself glows.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "sky/sky_model.h"

namespace skypol::sky {

inline constexpr double kSunAngularRadiusDeg = 0.2666;  // mean apparent solar semi-diameter

class CloudySky;

class SunDiscSky final : public SkyModel {
 public:
  // radiance: S0 added inside the disc, ≥ 0, in the sky's relative units (the solar disc is
  // ~2·10⁵ times as bright as the clear zenith sky in the visible).
  SunDiscSky(std::unique_ptr<SkyModel> inner, double radiance);
  std::string name() const override { return inner_->name(); }
  Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const override;
  void stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const override;
  double radiance() const { return radiance_; }
  const SkyModel& inner() const { return *inner_; }

 private:
  std::unique_ptr<SkyModel> inner_;
  double radiance_;
  const CloudySky* clouds_ = nullptr;  // the inner model if it is cloudy (not owned separately)
};

}  // namespace skypol::sky
