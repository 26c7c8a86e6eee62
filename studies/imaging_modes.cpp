// The sky through each ideal mapping on one grid, and the paper's ε (imaging_modes.h).
#include "studies/imaging_modes.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "camera/camera.h"
#include "camera/orientation.h"
#include "render/renderer.h"
#include "sky/units.h"

namespace skypol::studies {
namespace {

// Wrapped to (−90, 90] degrees: AoP is an axis, defined modulo 180°.
double wrap90(double deg) {
  double w = std::remainder(deg, 180.0);
  return w <= -90.0 ? w + 180.0 : w;
}

}  // namespace

ModeImage render_mode(camera::Mapping mapping, int size, double fov_deg, const sky::SkyModel& sky,
                      const sky::Sun& sun) {
  if (size < 2) throw std::invalid_argument("render_mode: size must be >= 2");
  const double theta_max = 0.5 * fov_deg * kRadPerDeg;
  camera::Intrinsics k;
  k.width = k.height = size;
  k.cx = k.cy = 0.5 * (size - 1);
  // The radius function of the mapping, for f: a throwaway lens of focal 1 gives r(θmax).
  k.fx = k.fy = 1.0;
  const double r_max = camera::RadialLens(mapping, k, theta_max).radius(theta_max);
  k.fx = k.fy = 0.5 * size / r_max;
  auto lens = std::make_shared<camera::RadialLens>(mapping, k, theta_max);
  auto cam = std::make_shared<camera::Camera>(lens, camera::world_from_heading_tilt_roll(0, 0, 0));

  render::RenderOptions options;
  options.channels = {"DoLP", "AoLP", "mask"};
  const render::Renderer renderer(cam, options);
  const stack::Frame frame = renderer.render(sky, sun);
  const auto& dolp = frame.channel("DoLP.Y");
  const auto& aolp = frame.channel("AoLP.Y");
  const auto& mask = frame.channel("mask");

  ModeImage m;
  m.mapping = mapping;
  m.size = size;
  m.fov_deg = fov_deg;
  const std::size_t n = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  m.dop.assign(n, 0.0f);
  m.aop_deg.assign(n, 0.0f);
  m.theta_deg.assign(n, 0.0f);
  m.azimuth_deg.assign(n, 0.0f);
  m.inside.assign(n, 0);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(size) +
                            static_cast<std::size_t>(x);
      if (mask[i] <= 0) continue;
      const auto d_cam = lens->ray(Eigen::Vector2d(x, y));
      if (!d_cam) continue;
      const Eigen::Vector3d d = cam->world_from_camera() * *d_cam;
      // Sensor AoLP is measured from the transported camera +x; the meridian lies at the pixel's
      // image angle φ from it (camera.h, meridional_e0), so AoLP_meridian = AoLP − φ and the
      // paper's α = −AoLP_meridian.
      const double phi = std::atan2(d_cam->y(), d_cam->x());
      m.inside[i] = 1;
      m.dop[i] = dolp[i];
      m.aop_deg[i] = static_cast<float>(wrap90((phi - static_cast<double>(aolp[i])) / kRadPerDeg));
      m.theta_deg[i] = static_cast<float>(std::acos(std::clamp(d.z(), -1.0, 1.0)) / kRadPerDeg);
      m.azimuth_deg[i] = static_cast<float>(sky::azimuth_of(d) / kRadPerDeg);
    }
  return m;
}

std::vector<float> dop_difference(const ModeImage& a, const ModeImage& b) {
  if (a.size != b.size) throw std::invalid_argument("dop_difference: image sizes differ");
  std::vector<float> d(a.dop.size(), 0.0f);
  for (std::size_t i = 0; i < d.size(); ++i)
    if (a.inside[i] && b.inside[i]) d[i] = a.dop[i] - b.dop[i];
  return d;
}

std::vector<float> aop_difference_deg(const ModeImage& a, const ModeImage& b) {
  if (a.size != b.size) throw std::invalid_argument("aop_difference_deg: image sizes differ");
  std::vector<float> d(a.aop_deg.size(), 0.0f);
  for (std::size_t i = 0; i < d.size(); ++i)
    if (a.inside[i] && b.inside[i])
      d[i] = static_cast<float>(wrap90(static_cast<double>(a.aop_deg[i]) - static_cast<double>(b.aop_deg[i])));
  return d;
}

Similarity similarity(const ModeImage& a, const ModeImage& b, const sky::Sun& sun,
                      const Region& region, double threshold_deg) {
  if (a.size != b.size) throw std::invalid_argument("similarity: image sizes differ");
  const std::vector<float> d = aop_difference_deg(a, b);
  const double sun_az = sun.azimuth;
  Similarity s;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (!a.inside[i] || !b.inside[i] || static_cast<double>(a.theta_deg[i]) > region.max_theta_deg) continue;
    if (region.anti_sun_half) {
      // Strictly more than 90° of azimuth from the sun (the zenith pixel, whose azimuth is
      // undefined, does not count).
      const double da = static_cast<double>(a.azimuth_deg[i]) * kRadPerDeg - sun_az;
      if (!(std::cos(da) < 0) || a.theta_deg[i] <= 0) continue;
    }
    ++s.pixels;
    if (std::abs(static_cast<double>(d[i])) < threshold_deg) ++s.similar;
  }
  s.epsilon = s.pixels > 0 ? static_cast<double>(s.similar) / static_cast<double>(s.pixels) : 0.0;
  return s;
}

}  // namespace skypol::studies
