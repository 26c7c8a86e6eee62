// The per-pixel sky mask (sky_mask.h).
#include "skypole/sky_mask.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "skypole/sun_vector.h"

namespace skypol::skypole {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kMinDolpForAolp = 0.05;  // below, the AoLP is mostly noise

const std::vector<float>* channel(const stack::Frame& f, const std::string& name) {
  const auto it = f.channels.find(name);
  return it == f.channels.end() ? nullptr : &it->second;
}

}  // namespace

std::optional<Eigen::Vector3d> e_vector(const Eigen::Vector3d& d, double a, camera::Transport t) {
  if (t == camera::Transport::meridional) {
    const Eigen::Vector3d e0 = camera::meridional_e0(d);
    return Eigen::Vector3d(std::cos(a) * e0 + std::sin(a) * d.cross(e0));
  }
  if (std::abs(d.z()) < 1e-3) return std::nullopt;  // E along the axis: the sensor angle says nothing
  Eigen::Vector3d e(std::cos(a), std::sin(a), -(std::cos(a) * d.x() + std::sin(a) * d.y()) / d.z());
  return Eigen::Vector3d(e.normalized());
}

SkyMask compute_sky_mask(const SkyImages& sky, const stack::Stack& stack, const SkyMaskParams& p) {
  SkyMask out;
  const std::size_t n = sky.pixels(), frames = sky.frames();
  out.masked.assign(n, 0);
  out.suns.assign(frames, std::nullopt);
  if (frames == 0 || !stack.camera) return out;
  const std::string aolp_name = "AoLP." + sky.band, s0_name = "S0." + sky.band;
  bool have_aolp = true, have_s0 = true;
  for (const stack::Frame& f : stack.frames) {
    const auto* a = channel(f, aolp_name);
    const auto* s = channel(f, s0_name);
    have_aolp = have_aolp && a && a->size() == n;
    have_s0 = have_s0 && s && s->size() == n;
  }
  const camera::Transport transport = stack.camera->transport();

  // Each frame's sun, robustly (the fits reject what they cannot explain, sun_vector.cpp).
  std::vector<std::optional<Eigen::Vector3d>> starts;
  if (!have_aolp) starts = find_suns(sky, filter_all(sky, default_filter_radius_px(sky.width, sky.height)));
  tbb::parallel_for(std::size_t{0}, frames, [&](std::size_t f) {
    if (have_aolp)
      out.suns[f] = sun_from_aolp(sky, sky.dolp[f], stack.frames[f].channels.at(aolp_name), *stack.camera,
                                  kMinDolpForAolp);
    else if (starts[f])
      out.suns[f] = sun_from_dolp(sky, sky.dolp[f], *starts[f]);
  });

  // Per frame, per pixel: judged (could be), bad (was), and why.
  enum : std::uint8_t { kLow = 1, kAolp = 2, kSat = 4, kDark = 8 };
  std::vector<std::vector<std::uint8_t>> why(frames, std::vector<std::uint8_t>(n, 0));
  std::vector<std::vector<std::uint8_t>> judged(frames, std::vector<std::uint8_t>(n, 0));
  tbb::parallel_for(std::size_t{0}, frames, [&](std::size_t f) {
    const std::vector<float>& dolp = sky.dolp[f];
    if (have_s0) {
      const std::vector<float>& s0 = stack.frames[f].channels.at(s0_name);
      std::vector<double> v;
      for (std::size_t i = 0; i < n; ++i)
        if (sky.valid[i] && std::isfinite(s0[i])) v.push_back(s0[i]);
      const double top = v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
      const double median = quantile(v, 0.5);
      for (std::size_t i = 0; i < n; ++i) {
        if (!sky.valid[i]) continue;
        judged[f][i] = 1;
        if (!(static_cast<double>(s0[i]) < p.saturated * top)) why[f][i] |= kSat;
        if (!(static_cast<double>(s0[i]) > p.dark * median)) why[f][i] |= kDark;
      }
    }
    if (!out.suns[f]) return;
    const Eigen::Vector3d s = *out.suns[f];
    std::vector<double> shape(n, 0.0), ratios;
    for (std::size_t i = 0; i < n; ++i) {
      if (!sky.valid[i]) continue;
      const double c = s.dot(to_double(sky.ray_camera[i]));
      shape[i] = (1 - c * c) / (1 + c * c);
      if (shape[i] >= p.min_shape) ratios.push_back(static_cast<double>(dolp[i]) / shape[i]);
    }
    if (ratios.size() < 20) return;
    const double pmax = quantile(ratios, 0.9);
    std::vector<double> res(n, -1.0), good_res;
    for (std::size_t i = 0; i < n; ++i) {
      if (!sky.valid[i] || shape[i] < p.min_shape) continue;
      judged[f][i] = 1;
      if (!(static_cast<double>(dolp[i]) >= p.low_ratio * pmax * shape[i])) {
        why[f][i] |= kLow;
        continue;
      }
      if (!have_aolp || !(static_cast<double>(dolp[i]) >= kMinDolpForAolp)) continue;
      const auto e = e_vector(to_double(sky.ray_camera[i]), stack.frames[f].channels.at(aolp_name)[i], transport);
      if (!e) continue;
      res[i] = std::asin(std::min(1.0, std::abs(e->dot(s))));
      good_res.push_back(res[i]);
    }
    if (good_res.size() < 20) return;
    const double cut = std::max(p.aolp_min_deg * kDeg, 4 * 1.4826 * quantile(good_res, 0.5));
    for (std::size_t i = 0; i < n; ++i)
      if (res[i] > cut) why[f][i] |= kAolp;
  });

  for (std::size_t i = 0; i < n; ++i) {
    if (!sky.valid[i]) continue;
    int j = 0, b = 0;
    std::uint8_t any = 0;
    for (std::size_t f = 0; f < frames; ++f) {
      j += judged[f][i];
      b += why[f][i] ? 1 : 0;
      any |= why[f][i];
    }
    out.low_dolp += (any & kLow) ? 1 : 0;
    out.wrong_aolp += (any & kAolp) ? 1 : 0;
    out.saturated += (any & kSat) ? 1 : 0;
    out.dark += (any & kDark) ? 1 : 0;
    if (b > 0 && b >= p.bad_share * j) {
      out.masked[i] = 1;
      ++out.masked_count;
    }
  }
  return out;
}

SkyMask apply_sky_mask(SkyImages& sky, const stack::Stack& stack, const SkyMaskParams& p) {
  SkyMask m = compute_sky_mask(sky, stack, p);
  if (sky.valid_count - m.masked_count < 50) return m;
  for (std::size_t i = 0; i < sky.pixels(); ++i)
    if (m.masked[i]) {
      sky.valid[i] = 0;
      sky.ray_camera[i] = Eigen::Vector3f::Zero();
    }
  sky.valid_count -= m.masked_count;
  return m;
}

}  // namespace skypol::skypole
