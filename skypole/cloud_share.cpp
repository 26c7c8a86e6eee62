// The unpolarized share of the sky (cloud_share.h).
#include "skypole/cloud_share.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "sky/units.h"

namespace skypol::skypole {

UnreadableSky unreadable_share(const SkyImages& sky, std::size_t f, const std::optional<Eigen::Vector3d>& sun) {
  const double cos40 = std::cos(rad_from_deg(40.0));
  const std::vector<float>& img = sky.dolp[f];
  const float cut = 0.2f * valid_quantile(img, sky, 0.99);
  std::size_t low = 0, clipped = 0, counted = 0;
  const auto away = [&](const Eigen::Vector3f& ray) {  // not near the sun (c > 0) or the antisun (c < 0)
    return !sun || std::abs(ray.cast<double>().dot(*sun)) <= cos40;
  };
  for (std::size_t i = 0; i < img.size(); ++i) {
    if (!sky.valid[i] || !away(sky.ray_camera[i])) continue;
    ++counted;
    low += img[i] < cut ? 1 : 0;
  }
  for (const Eigen::Vector3f& r : sky.clipped_rays) {  // sky the sensor could not read
    if (!away(r)) continue;
    ++counted;
    ++clipped;
  }
  if (counted == 0) return {};
  return {static_cast<double>(low + clipped) / static_cast<double>(counted),
          static_cast<double>(clipped) / static_cast<double>(counted)};
}

UnreadableSky unreadable_sky(const SkyImages& sky) {
  if (sky.frames() == 0 || sky.valid_count == 0) return {};
  const auto suns = find_suns(sky, sky.dolp);
  UnreadableSky total;
  for (std::size_t f = 0; f < sky.frames(); ++f) {
    const UnreadableSky share = unreadable_share(sky, f, suns[f]);
    total.unpolarized += share.unpolarized;
    total.clipped += share.clipped;
  }
  const auto frames = static_cast<double>(sky.frames());
  return {total.unpolarized / frames, total.clipped / frames};
}

std::optional<double> ring_spread(const SkyImages& sky, std::size_t f, const std::optional<Eigen::Vector3d>& sun) {
  if (!sun) return std::nullopt;
  constexpr int kSectors = 8;
  const double cos_in = std::cos(rad_from_deg(15.0)), cos_out = std::cos(rad_from_deg(35.0));
  const Eigen::Vector3d s = sun->normalized();
  const Eigen::Vector3d e1 = s.unitOrthogonal(), e2 = s.cross(e1);
  const std::vector<float>& img = sky.dolp[f];
  double sum[kSectors] = {};
  int n[kSectors] = {};
  for (std::size_t i = 0; i < img.size(); ++i) {
    if (!sky.valid[i]) continue;
    const Eigen::Vector3d d = sky.ray_camera[i].cast<double>();
    const double c = d.dot(s);
    if (c > cos_in || c < cos_out) continue;
    const double psi = std::atan2(d.dot(e2), d.dot(e1)) + std::numbers::pi;  // [0, 2π]
    const int k = std::min(kSectors - 1, static_cast<int>(psi / (2 * std::numbers::pi) * kSectors));
    sum[k] += static_cast<double>(img[i]);
    ++n[k];
  }
  double lo = 1e30, hi = -1e30;
  int used = 0;
  for (int k = 0; k < kSectors; ++k) {
    if (n[k] < 5) continue;
    const double m = sum[k] / n[k];
    lo = std::min(lo, m);
    hi = std::max(hi, m);
    ++used;
  }
  const double p99 = static_cast<double>(valid_quantile(img, sky, 0.99));
  if (used < 4 || !(p99 > 0)) return std::nullopt;
  return (hi - lo) / p99;
}

double ring_anisotropy(const SkyImages& sky) {
  if (sky.frames() == 0 || sky.valid_count == 0) return 0.0;
  const auto suns = find_suns(sky, sky.dolp);
  double total = 0;
  int frames = 0;
  for (std::size_t f = 0; f < sky.frames(); ++f)
    if (const std::optional<double> a = ring_spread(sky, f, suns[f])) {
      total += *a;
      ++frames;
    }
  return frames ? total / frames : 0.0;
}

}  // namespace skypol::skypole
