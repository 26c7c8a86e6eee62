#include "sky/sun_disc.h"

#include <cassert>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sky/clouds.h"
#include "sky/units.h"

namespace skypol::sky {
namespace {
const double kCosSunRadius = std::cos(rad_from_deg(kSunAngularRadiusDeg));
}  // namespace

SunDiscSky::SunDiscSky(std::unique_ptr<SkyModel> inner, double radiance)
    : inner_(std::move(inner)), radiance_(radiance) {
  if (!inner_) throw std::invalid_argument("SunDiscSky needs an inner model");
  if (!(std::isfinite(radiance_) && radiance_ >= 0.0)) {
    throw std::invalid_argument("sun_disc_radiance " + std::to_string(radiance_) + " must be ≥ 0");
  }
  clouds_ = dynamic_cast<const CloudySky*>(inner_.get());
}

Stokes SunDiscSky::stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const {
  Stokes s = inner_->stokes(d, e0, sun);
  if (d.dot(sun.direction) >= kCosSunRadius) {
    s.s0 += radiance_ * (clouds_ ? 1.0 - clouds_->opacity(d) : 1.0);
  }
  return s;
}

void SunDiscSky::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  if (out.size() < rays.size()) rays = rays.first(out.size());
  inner_->stokes(rays, sun, out.first(rays.size()));
  const Eigen::Vector3f s = sun.direction.cast<float>();
  const float cos_disc = static_cast<float>(kCosSunRadius);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays[i].d.dot(s) >= cos_disc) {  // a handful of rays per frame
      const double t = clouds_ ? 1.0 - clouds_->opacity(rays[i].d.cast<double>()) : 1.0;
      out[i].s0 += static_cast<float>(radiance_ * t);
    }
  }
}

}  // namespace skypol::sky
