#include "stack/polarization_math.h"

namespace skypol::stack {

sky::StokesF to_projected(const camera::Camera& camera, const sky::ViewRay& ray, const sky::StokesF& s) {
  const double l = std::hypot(double{s.s1}, double{s.s2});
  if (l == 0) return s;
  camera::CameraRay r{ray.d.cast<double>(), ray.e0.cast<double>()};
  const double angle = camera.sensor_angle(r, 0.5 * std::atan2(double{s.s2}, double{s.s1}));
  return {s.s0, static_cast<float>(l * std::cos(2 * angle)), static_cast<float>(l * std::sin(2 * angle)), s.s3};
}

}  // namespace skypol::stack
