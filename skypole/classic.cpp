// The paper's SkyPole algorithm (steps in classic.h).
#include "skypole/classic.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <stdexcept>
#include <type_traits>

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "sky/units.h"
#include "skypole/enum_names.h"

namespace skypol::skypole {
namespace {

// 8-connected blobs of `on` pixels; returns the label image (0 = off) and the blob count.
int label_blobs(const std::vector<std::uint8_t>& on, int w, int h, std::vector<int>& label) {
  label.assign(on.size(), 0);
  int n = 0;
  std::vector<std::size_t> stack;
  const std::size_t W = static_cast<std::size_t>(w);
  for (std::size_t start = 0; start < on.size(); ++start) {
    if (!on[start] || label[start]) continue;
    ++n;
    label[start] = n;
    stack.push_back(start);
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      const int x = static_cast<int>(i % W), y = static_cast<int>(i / W);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const std::size_t j = static_cast<std::size_t>(yy) * W + static_cast<std::size_t>(xx);
          if (on[j] && !label[j]) {
            label[j] = n;
            stack.push_back(j);
          }
        }
    }
  }
  return n;
}

// A valid pixel next to an invalid one or the image border.
bool on_edge(const SkyImages& sky, std::size_t i) {
  const std::size_t W = static_cast<std::size_t>(sky.width);
  const int x = static_cast<int>(i % W), y = static_cast<int>(i / W);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = x + dx, yy = y + dy;
      if (xx < 0 || yy < 0 || xx >= sky.width || yy >= sky.height) return true;
      if (!sky.valid[static_cast<std::size_t>(yy) * W + static_cast<std::size_t>(xx)]) return true;
    }
  return false;
}

// What the invalid neighbours of pixel i are (sky_images.h why_unusable): sets `field` for the edge
// of the field of view, `masked` for masked sky.
void unusable_neighbours(const SkyImages& sky, std::size_t i, bool& field, bool& masked) {
  const std::size_t W = static_cast<std::size_t>(sky.width);
  const int x = static_cast<int>(i % W), y = static_cast<int>(i / W);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = x + dx, yy = y + dy;
      const bool inside = xx >= 0 && yy >= 0 && xx < sky.width && yy < sky.height;
      if (inside && sky.valid[static_cast<std::size_t>(yy) * W + static_cast<std::size_t>(xx)]) continue;
      (why_unusable(sky, xx, yy) == Unusable::field_edge ? field : masked) = true;
    }
}

// A maximum wider than this (RMS radius) localises nothing, wherever its centre: it lies above the
// radii of the paper's protocol's valid answers and well below those of the maxima a short window
// spreads over the sky (docs/calibration-history.md, "Measurements behind the code's constants").
constexpr double kWideMaximumDeg = 20.0;

// Robust σ of the (filtered) difference image's noise: the MAD of differences between pixels
// 2⌊r⌋+1 apart along rows (far enough apart for the disk filter to leave them independent),
// divided by √2. The smooth signal adds little at that distance.
float difference_noise(const std::vector<float>& fa, const std::vector<float>& fb,
                       const SkyImages& sky, double radius) {
  const int step = 2 * static_cast<int>(std::floor(radius)) + 1;
  std::vector<double> d;
  const std::size_t W = static_cast<std::size_t>(sky.width);
  for (int y = 0; y < sky.height; y += 2)
    for (int x = 0; x + step < sky.width; x += 2) {
      const std::size_t i = static_cast<std::size_t>(y) * W + static_cast<std::size_t>(x);
      const std::size_t j = i + static_cast<std::size_t>(step);
      if (!sky.valid[i] || !sky.valid[j]) continue;
      d.push_back(std::abs(static_cast<double>(fa[j] - fb[j]) - static_cast<double>(fa[i] - fb[i])));
    }
  if (d.empty()) return 0.0f;
  return static_cast<float>(1.4826 * quantile(std::move(d), 0.5, QuantileRank::upper) / std::sqrt(2.0));
}

}  // namespace

constexpr EnumNames<ThresholdMode, 2> kThresholdModeNames{
    {{ThresholdMode::absolute, "absolute"}, {ThresholdMode::relative, "relative"}}};

ThresholdMode parse_threshold_mode(std::string_view name) {
  return enum_from_name(kThresholdModeNames, name, "threshold mode");
}
std::string_view threshold_mode_name(ThresholdMode m) { return enum_name(kThresholdModeNames, m); }

ClassicResult estimate_classic(const stack::Stack& stack, const ClassicParams& params) {
  return classic_from(prepare_classic(stack, params), params);
}

std::size_t classic_min_frames(const ClassicParams& params) {
  return params.pairs == PairMode::interval ? static_cast<std::size_t>(params.interval) + 2 : 3;
}

namespace {

void check_params(const ClassicParams& params) {
  if (params.pairs == PairMode::interval && params.interval < 1)
    throw std::invalid_argument("classic: pair interval must be ≥ 1 frame, got " +
                                std::to_string(params.interval));
  if (!(params.threshold > 0) || !std::isfinite(params.threshold))
    throw std::invalid_argument("classic: threshold must be > 0, got " +
                                std::to_string(params.threshold));
}

// Step 1 on a prepared sky (the parameters checked): each frame's DoLP filtered.
ClassicPrepared filtered_sky(SkyImages sky, const ClassicParams& params) {
  ClassicPrepared out;
  out.sky = std::move(sky);
  out.radius_px = params.filter_radius_px.value_or(default_filter_radius_px(out.sky.width, out.sky.height));
  out.filtered = filter_all(out.sky, out.radius_px);
  return out;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

ClassicPrepared prepare_classic(const stack::Stack& stack, const ClassicParams& params) {
  const auto t_start = std::chrono::steady_clock::now();
  check_params(params);  // before the stack is read: a bad parameter is named first
  ClassicPrepared out =
      filtered_sky(prepare_sky_images(stack, params.input, classic_min_frames(params), "classic"), params);
  out.seconds = seconds_since(t_start);
  return out;
}

ClassicPrepared prepare_classic(SkyImages sky, const ClassicParams& params) {
  const auto t_start = std::chrono::steady_clock::now();
  check_params(params);
  ClassicPrepared out = filtered_sky(std::move(sky), params);
  out.seconds = seconds_since(t_start);
  return out;
}

namespace {

// Steps 2 and 3 of one pair: |fa − fb| into `diff` at the valid pixels (its other pixels are left
// as they are: 0 in every pair), and the threshold the binary image applies to it.
float pair_difference(const std::vector<float>& fa, const std::vector<float>& fb, const SkyImages& sky, double radius,
                      const ClassicParams& params, std::vector<float>& diff) {
  const std::size_t n = sky.pixels();
  if (diff.empty()) diff.assign(n, 0.0f);
  for (std::size_t i = 0; i < n; ++i)
    if (sky.valid[i]) diff[i] = std::abs(fa[i] - fb[i]);
  float thr = static_cast<float>(params.threshold);
  if (params.threshold_mode == ThresholdMode::relative) {
    thr *= valid_quantile(diff, sky, 0.99);
    if (params.noise_floor > 0)
      thr = std::max(thr, static_cast<float>(params.noise_floor) * difference_noise(fa, fb, sky, radius));
  }
  return thr;
}

// Steps 5 and 6 from `sum`, the sum of the binary images of `pairs` pairs: the maximal blob, its
// checks and its pole. suns() gives find_suns of the frames the pairs read, asked for only when the
// blob is usable. `im` (optional) receives the sum and the blob.
PoleEstimate classic_answer(const SkyImages& sky, const std::vector<float>& sum, std::size_t pairs,
                            const std::function<std::vector<std::optional<Eigen::Vector3d>>()>& suns,
                            const ClassicParams& params, ClassicImages* im) {
  const char* method = "classic";
  const std::size_t n = sky.pixels();
  float best = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (sky.valid[i]) best = std::max(best, sum[i]);
  std::vector<std::uint8_t> maxset(n, 0);
  for (std::size_t i = 0; i < n; ++i) maxset[i] = sky.valid[i] && sum[i] == best && best > 0;
  std::vector<int> label;
  const int blobs = label_blobs(maxset, sky.width, sky.height, label);
  std::vector<std::size_t> size(static_cast<std::size_t>(blobs) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) size[static_cast<std::size_t>(label[i])] += label[i] ? 1 : 0;
  int chosen = 0;
  for (int b = 1; b <= blobs; ++b)
    if (chosen == 0 || size[static_cast<std::size_t>(b)] > size[static_cast<std::size_t>(chosen)])
      chosen = b;  // labels are assigned in first-pixel order, so ties keep the earliest blob
  if (im) {
    im->sum = sum;
    im->maximum.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) im->maximum[i] = chosen != 0 && label[i] == chosen;
  }

  if (chosen == 0 || best == 0)
    return invalid_estimate(method, "no pixel has a difference below the threshold in "
                                    "any pair (threshold too low?)");
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  bool touches_edge = false;
  for (std::size_t i = 0; i < n; ++i)
    if (label[i] == chosen) {
      centroid += to_double(sky.ray_camera[i]);
      touches_edge = touches_edge || on_edge(sky, i);
    }
  centroid.normalize();
  double sq = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (label[i] == chosen) {
      const Eigen::Vector3d d = to_double(sky.ray_camera[i]);
      const double a = std::atan2(d.cross(centroid).norm(), d.dot(centroid));
      sq += a * a;
    }
  const double residual = std::sqrt(sq / static_cast<double>(size[static_cast<std::size_t>(chosen)])) / kRadPerDeg;

  if (touches_edge) {
    // Which cause the maximum points to. One that spills over the edge because it is wide (its
    // centre farther inside than its own RMS radius, or wider than kWideMaximumDeg) was never
    // localised: a short, sparse or noisy window, whatever edge it touches. A compact one may point
    // past what it touches — beyond the field of view, or behind masked sky (cloud, clipping) — but
    // in the calibration study most compact maxima at the field's edge have the pole well inside
    // the field (a peak of the differences elsewhere), so the decline names both causes and claims
    // neither.
    const double share = static_cast<double>(size[static_cast<std::size_t>(chosen)]) / std::max(sky.valid_count, 1);
    double edge_deg = 180.0;
    for (std::size_t i = 0; i < n; ++i)
      if (sky.valid[i] && on_edge(sky, i)) {
        const Eigen::Vector3d d = to_double(sky.ray_camera[i]);
        edge_deg = std::min(edge_deg, std::atan2(d.cross(centroid).norm(), d.dot(centroid)) / kRadPerDeg);
      }
    bool field = false, masked = false;
    for (std::size_t i = 0; i < n; ++i)
      if (label[i] == chosen) unusable_neighbours(sky, i, field, masked);
    const Unusable hit = masked ? Unusable::masked_sky : Unusable::field_edge;
    const bool diffuse = edge_deg > residual || residual > kWideMaximumDeg;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  " (%.1f %% of the sky, RMS radius %.1f°, centre %.1f° from the edge, reached by %d of %zu pairs)",
                  100 * share, residual, edge_deg, static_cast<int>(best), pairs);
    const std::string what = "the maximum of the summed binary images";
    std::string why;
    if (diffuse)
      why = what + " is diffuse" + buf + " and touches " + std::string(unusable_words(hit)) +
            ": the differences do not localise the pole (window too short, frames too few or too noisy; "
            "or, less likely, the pole outside the field of view)";
    else
      why = what + buf + (masked ? " runs into " : " touches ") + std::string(unusable_words(hit)) + ": " +
            std::string(pole_beyond_words(hit)) + (masked && field ? " or outside the field of view" : "") +
            ", or the differences peak there instead (a short or noisy window)";
    return invalid_estimate(method, why);
  }

  // North or south: the sun's sense of rotation about the axis found (the pole above horizon).
  const HemisphereDecision hemi = decide_hemisphere(suns(), centroid, params.input.hemisphere);
  if (!hemi.ok) return invalid_estimate(method, hemi.why);
  PoleEstimate e = make_estimate(method, sky, hemi.is_north ? centroid : Eigen::Vector3d(-centroid), params.input);
  e.note += (e.note.empty() ? "" : "; ") + std::string("hemisphere from ") + hemi.source;
  e.residual_deg = residual;
  return e;
}

// The frames `keep_frame` keeps (nullptr or empty: all of `frames`), in order.
std::vector<int> kept_indices(std::size_t frames, const std::vector<std::uint8_t>* keep_frame) {
  std::vector<int> frame;
  for (int i = 0; i < static_cast<int>(frames); ++i)
    if (!keep_frame || keep_frame->empty() || (*keep_frame)[static_cast<std::size_t>(i)]) frame.push_back(i);
  return frame;
}

// The pairs of a run on the frames `frame` (stack indices), paired among themselves as a stack of
// only those frames would be; throws when they are too few.
std::vector<std::pair<int, int>> run_pairs(const std::vector<int>& frame, const ClassicParams& params) {
  const std::size_t min_frames = classic_min_frames(params);
  if (frame.size() < min_frames)
    throw std::invalid_argument("classic: needs at least " + std::to_string(min_frames) + " frames, got " +
                                std::to_string(frame.size()));
  std::vector<std::pair<int, int>> pairs = make_pairs(static_cast<int>(frame.size()), params.pairs, params.interval);
  for (auto& [a, b] : pairs) {
    a = frame[static_cast<std::size_t>(a)];
    b = frame[static_cast<std::size_t>(b)];
  }
  return pairs;
}

}  // namespace

ClassicResult classic_from(const ClassicPrepared& prepared, const ClassicParams& params,
                           const std::vector<std::uint8_t>* keep_frame) {
  const auto t_start = std::chrono::steady_clock::now();
  const SkyImages& sky = prepared.sky;
  const double radius = prepared.radius_px;
  // The frames kept, in order: pairs are made among them as for a stack of only those frames.
  const std::vector<int> frame = kept_indices(sky.frames(), keep_frame);
  ClassicResult result;
  ClassicImages& im = result.images;
  im.width = sky.width;
  im.height = sky.height;
  im.pairs = run_pairs(frame, params);
  FrameImages kept_filtered;  // find_suns reads the kept frames only
  for (int i : frame) kept_filtered.push_back(prepared.filtered[static_cast<std::size_t>(i)]);
  const std::vector<std::vector<float>>& filtered = prepared.filtered;

  const std::size_t n = sky.pixels();
  // Each pair on its own (in parallel), each thread with one difference image and its count of
  // low differences per pixel, reused from pair to pair: the memory is a few images whatever the
  // number of pairs. The sum adds the threads' counts, whole numbers, so its order does not matter.
  struct Scratch {
    std::vector<float> diff;
    std::vector<std::uint32_t> count;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  std::vector<std::vector<float>> diffs(params.keep_intermediates ? im.pairs.size() : 0);
  std::vector<std::vector<std::uint8_t>> bins(params.keep_intermediates ? im.pairs.size() : 0);
  im.thresholds.assign(im.pairs.size(), 0.0f);
  tbb::parallel_for(std::size_t{0}, im.pairs.size(), [&](std::size_t k) {
    const auto& fa = filtered[static_cast<std::size_t>(im.pairs[k].first)];
    const auto& fb = filtered[static_cast<std::size_t>(im.pairs[k].second)];
    Scratch& s = scratch.local();
    if (s.count.empty()) s.count.assign(n, 0);
    const float thr = pair_difference(fa, fb, sky, radius, params, s.diff);
    const std::vector<float>& diff = s.diff;
    for (std::size_t i = 0; i < n; ++i) s.count[i] += sky.valid[i] && diff[i] <= thr ? 1 : 0;
    im.thresholds[k] = thr;
    if (params.keep_intermediates) {
      bins[k].assign(n, 0);
      for (std::size_t i = 0; i < n; ++i) bins[k][i] = sky.valid[i] && diff[i] <= thr;
      diffs[k] = diff;
    }
  });
  std::vector<float> sum(n, 0.0f);
  for (const Scratch& s : scratch)
    for (std::size_t i = 0; i < n; ++i) sum[i] += static_cast<float>(s.count[i]);
  if (params.keep_intermediates) {
    im.differences = std::move(diffs);
    im.binaries = std::move(bins);
    for (std::size_t k = 0; k < kept_filtered.size(); ++k) im.filtered.push_back(kept_filtered[k]);
  }
  result.estimate = classic_answer(
      sky, sum, im.pairs.size(), [&] { return find_suns(sky, kept_filtered); }, params,
      params.keep_intermediates ? &im : nullptr);
  result.estimate.seconds =
      prepared.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return result;
}

ClassicRuns::ClassicRuns(const SkyImages& sky, const ClassicParams& params, std::size_t frames,
                         const std::vector<std::vector<std::uint8_t>>& keeps)
    : sky_(&sky),
      params_(params),
      radius_(params.filter_radius_px.value_or(default_filter_radius_px(sky.width, sky.height))),
      frames_(frames),
      suns_(frames) {
  check_params(params);
  params_.keep_intermediates = false;
  // Every run's pairs, and each distinct pair once (by its later frame, then its earlier one), with
  // the runs that read it.
  std::map<std::pair<int, int>, std::vector<std::size_t>> readers;
  for (const std::vector<std::uint8_t>& keep : keeps) {
    Run& run = runs_.emplace_back();
    run.frames = kept_indices(frames, &keep);
    run.pairs = run_pairs(run.frames, params_).size();
    for (const auto& [a, b] : run_pairs(run.frames, params_)) readers[{b, a}].push_back(runs_.size() - 1);
  }
  last_use_.assign(frames, -1);
  for (const auto& [ba, runs] : readers) {
    pairs_.push_back({ba.second, ba.first, runs});
    last_use_[static_cast<std::size_t>(ba.second)] = std::max(last_use_[static_cast<std::size_t>(ba.second)], ba.first);
    last_use_[static_cast<std::size_t>(ba.first)] = std::max(last_use_[static_cast<std::size_t>(ba.first)], ba.first);
  }
  filtered_.resize(frames);
}

void ClassicRuns::add(std::vector<float> filtered) {
  const std::size_t f = added_;
  if (f >= frames_) throw std::logic_error("ClassicRuns: more frames than announced");
  const SkyImages& sky = *sky_;
  const std::size_t n = sky.pixels();
  {
    FrameImages one;
    one.push_back(filtered);
    suns_[f] = find_suns(sky, one).front();  // find_suns reads each frame on its own
  }
  filtered_[f] = std::move(filtered);
  // The pairs that end at this frame, each on its own (in parallel); then their binary images
  // added to the counts of the runs that read them.
  std::vector<const Pair*> now;
  for (; next_pair_ < pairs_.size() && pairs_[next_pair_].b == static_cast<int>(f); ++next_pair_)
    now.push_back(&pairs_[next_pair_]);
  std::vector<std::vector<std::uint8_t>> low(now.size());
  tbb::parallel_for(std::size_t{0}, now.size(), [&](std::size_t k) {
    std::vector<float> diff;
    const float thr = pair_difference(filtered_[static_cast<std::size_t>(now[k]->a)],
                                      filtered_[static_cast<std::size_t>(now[k]->b)], sky, radius_, params_, diff);
    low[k].assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) low[k][i] = sky.valid[i] && diff[i] <= thr ? 1 : 0;
  });
  const auto add_to = [&](auto& count, const std::vector<std::uint8_t>& binary) {
    if (count.empty()) count.assign(n, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
        count[i] = static_cast<std::remove_reference_t<decltype(count[i])>>(count[i] + binary[i]);
    });
  };
  for (std::size_t k = 0; k < now.size(); ++k)
    for (const std::size_t r : now[k]->runs) {
      Run& run = runs_[r];
      if (run.pairs <= 0xffff)
        add_to(run.count16, low[k]);
      else
        add_to(run.count, low[k]);
    }
  // Frames no later pair reads are let go.
  for (std::size_t g = 0; g <= f; ++g)
    if (last_use_[g] <= static_cast<int>(f)) std::vector<float>().swap(filtered_[g]);
  ++added_;
}

PoleEstimate ClassicRuns::answer(std::size_t r) const {
  if (added_ != frames_) throw std::logic_error("ClassicRuns: not every frame was added");
  const Run& run = runs_[r];
  const SkyImages& sky = *sky_;
  std::vector<float> sum(sky.pixels(), 0.0f);
  for (std::size_t i = 0; i < run.count.size(); ++i) sum[i] = static_cast<float>(run.count[i]);
  for (std::size_t i = 0; i < run.count16.size(); ++i) sum[i] = static_cast<float>(run.count16[i]);
  return classic_answer(
      sky, sum, run.pairs,
      [&] {
        std::vector<std::optional<Eigen::Vector3d>> suns;
        for (const int f : run.frames) suns.push_back(suns_[static_cast<std::size_t>(f)]);
        return suns;
      },
      params_, nullptr);
}

std::size_t ClassicRuns::bytes() const {
  std::size_t b = suns_.capacity() * sizeof(suns_[0]) + last_use_.capacity() * sizeof(int) +
                  pairs_.capacity() * sizeof(Pair);
  for (const Run& run : runs_)
    b += run.count.capacity() * sizeof(std::uint32_t) + run.count16.capacity() * sizeof(std::uint16_t) +
         run.frames.capacity() * sizeof(int);
  for (const Pair& p : pairs_) b += p.runs.capacity() * sizeof(std::size_t);
  for (const std::vector<float>& f : filtered_) b += f.capacity() * sizeof(float) + sizeof(f);
  return b;
}

}  // namespace skypol::skypole
