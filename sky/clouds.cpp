// Procedural clouds. The threshold that turns noise into cloud is calibrated once, at
// construction, on 4096 directions spread evenly over the sphere (a Fibonacci lattice): the
// (1 − coverage) quantile of the noise there. So `coverage` means what it says whatever the
// noise's distribution, and the field depends only on the seed and the parameters.
#include "sky/clouds.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "sky/noise.h"
#include "sky/units.h"

namespace skypol::sky {
namespace {

constexpr int kOctaves = 4;
constexpr float kOctaveWeight = 1.0f + 0.5f + 0.25f + 0.125f;  // sum of the octaves' amplitudes
constexpr int kCalibrationPoints = 4096;

float smoothstep01(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// Octave o of the fractal sum uses its own seed so the octaves do not line up.
std::uint64_t octave_seed(std::uint64_t seed, int o) {
  return seed + static_cast<std::uint64_t>(o) * 0x632be59bd9b4e019ULL;
}

}  // namespace

void validate(const CloudParams& p) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
  };
  require(p.coverage >= 0.0 && p.coverage <= 1.0, "clouds.coverage " + std::to_string(p.coverage) + " must be in [0, 1]");
  require(p.scale_deg >= 1.0 && p.scale_deg <= 90.0,
          "clouds.scale_deg " + std::to_string(p.scale_deg) + " must be in [1, 90] degrees");
  require(p.softness > 0.0 && p.softness <= 1.0, "clouds.softness " + std::to_string(p.softness) + " must be in (0, 1]");
  require(p.brightness >= 1.0 && std::isfinite(p.brightness),
          "clouds.brightness " + std::to_string(p.brightness) + " must be ≥ 1 (clouds are brighter than the sky behind)");
}

CloudySky::CloudySky(std::unique_ptr<SkyModel> clear, CloudParams params)
    : clear_(std::move(clear)), params_(params) {
  if (!clear_) throw std::invalid_argument("CloudySky needs a clear-sky model");
  validate(params_);
  for (int o = 0; o < kOctaves; ++o) octaves_.emplace_back(octave_seed(params_.seed, o));
  // One lattice cell ≈ one cloud: a cell spans 1/frequency in direction space ≈ that many radians.
  frequency_ = static_cast<float>(1.0 / rad_from_deg(params_.scale_deg));
  if (params_.coverage <= 0.0) {
    threshold_ = std::numeric_limits<float>::infinity();
  } else if (params_.coverage >= 1.0) {
    threshold_ = -std::numeric_limits<float>::infinity();
  } else {
    std::vector<float> values(kCalibrationPoints);
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < kCalibrationPoints; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / kCalibrationPoints;
      const double r = std::sqrt(1.0 - z * z);
      const double phi = golden * i;
      values[static_cast<std::size_t>(i)] = fractal_noise_at(static_cast<float>(r * std::cos(phi)),
                                                             static_cast<float>(r * std::sin(phi)),
                                                             static_cast<float>(z));
    }
    const auto k = static_cast<std::size_t>((1.0 - params_.coverage) * (kCalibrationPoints - 1));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    threshold_ = values[k];
  }
}

float CloudySky::fractal_noise_at(float x, float y, float z) const {
  float sum = 0.0f, amplitude = 1.0f, frequency = frequency_;
  for (int o = 0; o < kOctaves; ++o) {
    sum += amplitude * octaves_[static_cast<std::size_t>(o)](x * frequency, y * frequency, z * frequency);
    amplitude *= 0.5f;
    frequency *= 2.0f;
  }
  return sum / kOctaveWeight;
}

// The same sum as fractal_noise_at, stopped as soon as the octaves still to come (each in
// [0, amplitude)) cannot move the value out of the saturated part of the edge ramp: the result is
// the same, about half the work on a half-cloudy sky.
float CloudySky::opacity_f(float x, float y, float z) const {
  if (std::isinf(threshold_)) return threshold_ > 0 ? 0.0f : 1.0f;
  const float half = 0.5f * static_cast<float>(params_.softness);
  const float lo = (threshold_ - half) * kOctaveWeight, hi = (threshold_ + half) * kOctaveWeight;
  float sum = 0.0f, amplitude = 1.0f, frequency = frequency_, remaining = kOctaveWeight;
  for (int o = 0; o < kOctaves; ++o) {
    sum += amplitude * octaves_[static_cast<std::size_t>(o)](x * frequency, y * frequency, z * frequency);
    remaining -= amplitude;
    if (sum + remaining <= lo) return 0.0f;
    if (sum >= hi) return 1.0f;
    amplitude *= 0.5f;
    frequency *= 2.0f;
  }
  return smoothstep01((sum / kOctaveWeight - threshold_) / static_cast<float>(params_.softness) + 0.5f);
}

double CloudySky::opacity(const Eigen::Vector3d& d) const {
  return opacity_f(static_cast<float>(d.x()), static_cast<float>(d.y()), static_cast<float>(d.z()));
}

Stokes CloudySky::stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const {
  const Stokes s = clear_->stokes(d, e0, sun);
  const double a = opacity(d);
  const double keep = 1.0 - a;
  return {s.s0 * (keep + a * params_.brightness), keep * s.s1, keep * s.s2, keep * s.s3};
}

void CloudySky::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  if (out.size() < rays.size()) rays = rays.first(out.size());
  clear_->stokes(rays, sun, out.first(rays.size()));
  const float brightness = static_cast<float>(params_.brightness);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const float a = opacity_f(rays[i].d.x(), rays[i].d.y(), rays[i].d.z());
    const float keep = 1.0f - a;
    StokesF& o = out[i];
    o.s0 *= keep + a * brightness;
    o.s1 *= keep;
    o.s2 *= keep;
    o.s3 *= keep;
  }
}

}  // namespace skypol::sky
