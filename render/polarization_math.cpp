#include "render/polarization_math.h"

#include <cmath>
#include <numbers>

namespace skypol::render {

std::vector<float> dolp_image(std::span<const float> s0, std::span<const float> s1, std::span<const float> s2) {
  std::vector<float> out(s0.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const float l = std::sqrt(s1[i] * s1[i] + s2[i] * s2[i]);
    out[i] = s0[i] > 0 ? std::min(1.0f, l / s0[i]) : 0.0f;
  }
  return out;
}

std::vector<float> aolp_image(std::span<const float> s1, std::span<const float> s2) {
  std::vector<float> out(s1.size());
  constexpr float half_pi = std::numbers::pi_v<float> / 2;
  for (std::size_t i = 0; i < out.size(); ++i) {
    float a = 0.5f * std::atan2(s2[i], s1[i]);
    if (a <= -half_pi) a = half_pi;  // atan2(−0, −x) = −π: keep the interval half-open
    out[i] = a;
  }
  return out;
}

sky::StokesF to_projected(const camera::Camera& camera, const sky::ViewRay& ray, const sky::StokesF& s) {
  const double l = std::hypot(double{s.s1}, double{s.s2});
  if (l == 0) return s;
  camera::CameraRay r{ray.d.cast<double>(), ray.e0.cast<double>()};
  const double angle = camera.sensor_angle(r, 0.5 * std::atan2(double{s.s2}, double{s.s1}));
  return {s.s0, static_cast<float>(l * std::cos(2 * angle)), static_cast<float>(l * std::sin(2 * angle)), s.s3};
}

}  // namespace skypol::render
