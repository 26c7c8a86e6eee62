// Physical intrinsics, binning and image-circle geometry, valid for any Lens.
#include "camera/intrinsics.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "sky/units.h"

namespace skypol::camera {

Intrinsics intrinsics_from_mm(double focal_mm, double pitch_um, int width, int height) {
  if (!(std::isfinite(focal_mm) && focal_mm > 0)) throw std::invalid_argument("focal_mm must be > 0");
  if (!(std::isfinite(pitch_um) && pitch_um > 0)) throw std::invalid_argument("pitch_um must be > 0");
  if (width < 1) throw std::invalid_argument("width must be > 0");
  if (height < 1) throw std::invalid_argument("height must be > 0");
  Intrinsics k;
  k.fx = k.fy = focal_mm / (pitch_um * 1e-3);
  k.cx = 0.5 * (width - 1);
  k.cy = 0.5 * (height - 1);
  k.width = width;
  k.height = height;
  return k;
}

std::shared_ptr<const Lens> binned(const Lens& lens, int b) {
  if (b < 1) throw std::invalid_argument("binning must be >= 1");
  return lens.rescaled(1.0 / b);
}

namespace {

constexpr int kRing = 720;  // azimuth samples per circle (0.5°)

Eigen::Vector3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

bool ring_on_sensor(const Lens& lens, double theta) {
  const auto& k = lens.intrinsics();
  for (int i = 0; i < kRing; ++i) {
    const auto p = lens.project(dir(theta, 2 * std::numbers::pi * i / kRing));
    if (!p || p->x() < -0.5 || p->y() < -0.5 || p->x() > k.width - 0.5 || p->y() > k.height - 0.5)
      return false;
  }
  return true;
}

}  // namespace

ImageCircle image_circle(const Lens& lens) {
  ImageCircle c;
  const double tmax = lens.max_field_angle();
  c.centre = lens.project({0, 0, 1}).value_or(Eigen::Vector2d(lens.intrinsics().cx, lens.intrinsics().cy));
  for (int i = 0; i < kRing; ++i)
    if (const auto p = lens.project(dir(tmax, 2 * std::numbers::pi * i / kRing)))
      c.radius_px = std::max(c.radius_px, (*p - c.centre).norm());
  c.max_fov_deg = deg_from_rad(2 * tmax);
  c.fits_on_sensor = ring_on_sensor(lens, tmax);
  double lo = 0, hi = tmax;
  if (c.fits_on_sensor) {
    lo = tmax;
  } else if (ring_on_sensor(lens, 0)) {
    for (int i = 0; i < 60; ++i) {  // rings grow with θ for every monotone model
      const double mid = 0.5 * (lo + hi);
      (ring_on_sensor(lens, mid) ? lo : hi) = mid;
    }
  }
  c.full_circle_fov_deg = deg_from_rad(2 * lo);
  return c;
}

}  // namespace skypol::camera
