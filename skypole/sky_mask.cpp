// The per-pixel sky mask (sky_mask.h).
#include "skypole/sky_mask.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>

#include <tbb/parallel_for.h>

#include "sky/units.h"
#include "skypole/sun_vector.h"

namespace skypol::skypole {
namespace {

constexpr double kMinDolpForAolp = kMaskMinDolp;  // below, the AoLP is mostly noise

const std::vector<float>* channel(const stack::Frame& f, const std::string& name) {
  const auto it = f.channels.find(name);
  return it == f.channels.end() ? nullptr : &it->second;
}

}  // namespace

std::pair<bool, bool> aolp_and_s0(const SkyImages& sky, const FrameRefs& frames) {
  const std::size_t n = sky.pixels();
  const std::string aolp_name = "AoLP." + sky.band, s0_name = "S0." + sky.band;
  bool have_aolp = true, have_s0 = true;
  for (const stack::Frame* f : frames) {
    const auto* a = channel(*f, aolp_name);
    const auto* s = channel(*f, s0_name);
    have_aolp = have_aolp && a && a->size() == n;
    have_s0 = have_s0 && s && s->size() == n;
  }
  return {have_aolp, have_s0};
}

SkyJudgments judge_sky(const SkyImages& sky, const FrameRefs& frames, const camera::Camera& camera,
                       const SkyMaskParams& p, const std::vector<const FrameEVectors*>* e_vectors,
                       const std::vector<std::optional<Eigen::Vector3d>>* aolp_suns) {
  SkyJudgments out;
  const std::size_t n = sky.pixels(), count = frames.size();
  out.suns.assign(count, std::nullopt);
  out.marks.assign(count, std::vector<std::uint8_t>(n, 0));
  std::tie(out.have_aolp, out.have_s0) = aolp_and_s0(sky, frames);
  const bool have_aolp = out.have_aolp, have_s0 = out.have_s0;
  const std::string aolp_name = "AoLP." + sky.band, s0_name = "S0." + sky.band;
  const camera::Transport transport = camera.transport();
  const auto cached = [&](std::size_t f) -> const FrameEVectors* { return e_vectors ? (*e_vectors)[f] : nullptr; };

  // Each frame's sun, robustly (the fits reject what they cannot explain, sun_vector.cpp).
  std::vector<std::optional<Eigen::Vector3d>> starts;
  if (!have_aolp) starts = find_suns(sky, filter_all(sky, default_filter_radius_px(sky.width, sky.height)));
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t f) {
    if (have_aolp && aolp_suns)
      out.suns[f] = (*aolp_suns)[f];
    else if (have_aolp)
      out.suns[f] = cached(f) ? sun_from_aolp(sky, sky.dolp[f], *cached(f), kMinDolpForAolp)
                              : sun_from_aolp(sky, sky.dolp[f], frames[f]->channels.at(aolp_name), camera,
                                              kMinDolpForAolp,
                                              polarizer_fit(*frames[f], PolarizerModel::from_stack));
    else if (starts[f])
      out.suns[f] = sun_from_dolp(sky, sky.dolp[f], *starts[f]);
  });

  // Per frame, per pixel: judged (could be), bad (was), and why.
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t f) {
    const std::vector<float>& dolp = sky.dolp[f];
    std::vector<std::uint8_t>& mark = out.marks[f];
    if (have_s0) {
      const std::vector<float>& s0 = frames[f]->channels.at(s0_name);
      std::vector<double> v;
      for (std::size_t i = 0; i < n; ++i)
        if (sky.valid[i] && std::isfinite(s0[i])) v.push_back(s0[i]);
      const double top = v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
      const double median = quantile(std::move(v), 0.5);
      for (std::size_t i = 0; i < n; ++i) {
        if (!sky.valid[i]) continue;
        mark[i] |= SkyJudgments::kJudged;
        if (!(static_cast<double>(s0[i]) < p.saturated * top)) mark[i] |= SkyJudgments::kSat;
        if (!(static_cast<double>(s0[i]) > p.dark * median)) mark[i] |= SkyJudgments::kDark;
      }
    }
    if (!out.suns[f]) return;
    const Eigen::Vector3d s = *out.suns[f];
    const auto shape = [&](std::size_t i) {
      const double c = s.dot(to_double(sky.ray_camera[i]));
      return (1 - c * c) / (1 + c * c);
    };
    std::vector<double> ratios;
    for (std::size_t i = 0; i < n; ++i) {
      if (!sky.valid[i]) continue;
      const double g = shape(i);
      if (g >= p.min_shape) ratios.push_back(static_cast<double>(dolp[i]) / g);
    }
    if (ratios.size() < 20) return;
    const double pmax = quantile(std::move(ratios), 0.9);
    const FrameEVectors* ev = cached(f);
    std::size_t k = 0;  // ev's cursor
    std::vector<std::pair<std::size_t, double>> res;  // the pixels whose E-vector was read, its angle out of plane
    std::vector<double> good_res;
    for (std::size_t i = 0; i < n; ++i) {
      if (!sky.valid[i]) continue;
      const double g = shape(i);
      if (g < p.min_shape) continue;
      mark[i] |= SkyJudgments::kJudged;
      if (!(static_cast<double>(dolp[i]) >= p.low_ratio * pmax * g)) {
        mark[i] |= SkyJudgments::kLow;
        continue;
      }
      if (!have_aolp || !(static_cast<double>(dolp[i]) >= kMinDolpForAolp)) continue;
      std::optional<Eigen::Vector3d> e;
      while (ev && k < ev->pixel.size() && ev->pixel[k] < i) ++k;
      if (ev && k < ev->pixel.size() && ev->pixel[k] == i) {
        if (ev->flags[k] & FrameEVectors::kDefined) e = ev->e[k];
      } else {
        e = e_vector(to_double(sky.ray_camera[i]), frames[f]->channels.at(aolp_name)[i], transport);
      }
      if (!e) continue;
      res.emplace_back(i, std::asin(std::min(1.0, std::abs(e->dot(s)))));
      good_res.push_back(res.back().second);
    }
    if (good_res.size() < 20) return;
    const double cut = std::max(p.aolp_min_deg * kRadPerDeg, 4 * 1.4826 * quantile(std::move(good_res), 0.5));
    for (const auto& [i, r] : res)
      if (r > cut) mark[i] |= SkyJudgments::kAolp;
  });
  return out;
}

namespace {

constexpr std::uint8_t kBad = SkyJudgments::kLow | SkyJudgments::kAolp | SkyJudgments::kSat | SkyJudgments::kDark;

// Pixel i's verdict from its frames' judgments: judged by `judged` frames, bad in b of them, for
// the causes `any`.
void verdict(SkyMask& out, std::size_t i, int judged, int b, std::uint8_t any, const SkyMaskParams& p) {
  out.low_dolp += (any & SkyJudgments::kLow) ? 1 : 0;
  out.wrong_aolp += (any & SkyJudgments::kAolp) ? 1 : 0;
  out.saturated += (any & SkyJudgments::kSat) ? 1 : 0;
  out.dark += (any & SkyJudgments::kDark) ? 1 : 0;
  if (b > 0 && b >= p.bad_share * judged) {
    out.masked[i] = 1;
    ++out.masked_count;
  }
}

}  // namespace

SkyMask mask_from_judgments(const SkyImages& sky, const SkyJudgments& j, const SkyMaskParams& p,
                            const std::vector<std::uint8_t>* keep) {
  SkyMask out;
  const std::size_t n = sky.pixels();
  out.masked.assign(n, 0);
  std::vector<std::size_t> frames;
  for (std::size_t f = 0; f < j.marks.size(); ++f)
    if (!keep || (*keep)[f]) {
      frames.push_back(f);
      out.suns.push_back(j.suns[f]);
    }
  for (std::size_t i = 0; i < n; ++i) {
    if (!sky.valid[i]) continue;
    int judged = 0, b = 0;
    std::uint8_t any = 0;
    for (const std::size_t f : frames) {
      const std::uint8_t why = j.marks[f][i] & kBad;
      judged += (j.marks[f][i] & SkyJudgments::kJudged) ? 1 : 0;
      b += why ? 1 : 0;
      any |= why;
    }
    verdict(out, i, judged, b, any, p);
  }
  return out;
}

JudgmentTally::JudgmentTally(std::size_t pixels) : judged_(pixels, 0), bad_(pixels, 0), any_(pixels, 0) {}

void JudgmentTally::add(const SkyJudgments& one) {
  if (one.marks.size() != 1 || one.marks[0].size() != any_.size())
    throw std::logic_error("JudgmentTally: one frame's judgments of the same sky expected");
  if (suns_.size() >= 0xffff) throw std::length_error("JudgmentTally: more than 65534 frames");
  const std::vector<std::uint8_t>& mark = one.marks[0];
  for (std::size_t i = 0; i < mark.size(); ++i) {
    const std::uint8_t why = mark[i] & kBad;
    judged_[i] = static_cast<std::uint16_t>(judged_[i] + ((mark[i] & SkyJudgments::kJudged) ? 1 : 0));
    bad_[i] = static_cast<std::uint16_t>(bad_[i] + (why ? 1 : 0));
    any_[i] |= why;
  }
  suns_.push_back(one.suns[0]);
}

SkyMask JudgmentTally::mask(const SkyImages& sky, const SkyMaskParams& p) const {
  SkyMask out;
  const std::size_t n = sky.pixels();
  out.masked.assign(n, 0);
  out.suns = suns_;
  for (std::size_t i = 0; i < n; ++i)
    if (sky.valid[i]) verdict(out, i, judged_[i], bad_[i], any_[i], p);
  return out;
}

std::size_t JudgmentTally::bytes() const {
  return judged_.capacity() * 2 + bad_.capacity() * 2 + any_.capacity() + suns_.capacity() * sizeof(suns_[0]);
}

SkyMask compute_sky_mask(const SkyImages& sky, const stack::Stack& stack, const SkyMaskParams& p) {
  if (sky.frames() == 0 || !stack.camera) {
    SkyMask out;
    out.masked.assign(sky.pixels(), 0);
    out.suns.assign(sky.frames(), std::nullopt);
    return out;
  }
  return mask_from_judgments(sky, judge_sky(sky, all_frames(stack), *stack.camera, p), p);
}

void apply_mask(SkyImages& sky, const SkyMask& m) {
  if (sky.valid_count - m.masked_count < 50) return;
  for (std::size_t i = 0; i < sky.pixels(); ++i)
    if (m.masked[i]) {
      sky.valid[i] = 0;
      sky.ray_camera[i] = Eigen::Vector3f::Zero();
    }
  sky.valid_count -= m.masked_count;
}

SkyMask apply_sky_mask(SkyImages& sky, const stack::Stack& stack, const SkyMaskParams& p) {
  SkyMask m = compute_sky_mask(sky, stack, p);
  apply_mask(sky, m);
  return m;
}

}  // namespace skypol::skypole
