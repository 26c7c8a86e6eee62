// classic on a stack read part by part (classic_stream.h).
#include "skypole/classic_stream.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include <tbb/parallel_invoke.h>

#include "stack/stack_io.h"
#include "skypole/classic.h"
#include "skypole/cloud_share.h"
#include "skypole/e_vectors.h"
#include "skypole/evaluate.h"
#include "skypole/report.h"
#include "skypole/sky_mask.h"
#include "skypole/stack_sky.h"
#include "skypole/sun_vector.h"
#include "skypole/uncertainty.h"

namespace skypol::skypole {
namespace {

// Of `channels`, those named.
std::vector<std::string> only(const std::vector<std::string>& channels, const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const std::string& c : channels)
    if (std::find(names.begin(), names.end(), c) != names.end()) out.push_back(c);
  return out;
}

// A frame's truth, size and exposure, without its channels.
stack::Frame without_channels(const stack::Frame& f) {
  stack::Frame out;
  out.width = f.width;
  out.height = f.height;
  out.truth = f.truth;
  out.exposure_us = f.exposure_us;
  return out;
}

std::size_t sky_bytes(const SkyImages& sky) {
  return sky.valid.capacity() + sky.ray_camera.capacity() * sizeof(Eigen::Vector3f) +
         sky.clipped_rays.capacity() * sizeof(Eigen::Vector3f) + sky.times_s.capacity() * sizeof(double);
}

// What pass 2 keeps of each frame for the readings, and the judgments' counts.
struct Readings {
  std::vector<UnreadableSky> unread;         // per frame, its share (unreadable_share)
  std::vector<std::optional<double>> ring;   // per frame, its spread (ring_spread)
  std::optional<JudgmentTally> tally;        // the sky mask's judgments (InputOptions::sky_mask)
  // Per frame, the misfit of its Rayleigh fit on the sky unmasked (nullopt: no fit), which is the
  // misfit's own when the mask leaves out no pixel.
  std::vector<std::optional<double>> unmasked_misfit;
  std::size_t bytes() const {
    return unread.capacity() * sizeof(UnreadableSky) + ring.capacity() * sizeof(ring[0]) +
           unmasked_misfit.capacity() * sizeof(unmasked_misfit[0]) + (tally ? tally->bytes() : 0);
  }
};

// One frame's part of rayleigh_law_misfit (sun_vector.h fit_rayleigh_law) on `sky`, whose dolp is
// that frame's: the Rayleigh fit from `start` and the misfit of the law it fits (nullopt when the
// fit fails). robust: InputOptions::sky_mask, as the fits there.
std::optional<double> frame_misfit(const SkyImages& sky, const std::optional<Eigen::Vector3d>& start, bool robust) {
  if (!start) return std::nullopt;
  double pmax = 0, rms = 1.0;
  const std::optional<Eigen::Vector3d> sun = sun_from_dolp(sky, sky.dolp[0], *start, &pmax, &rms, robust);
  if (!sun) return std::nullopt;
  return rayleigh_misfit(sky, sky.dolp[0], *sun, pmax);
}

// The median of the frames' misfits, 1 if no frame has one (rayleigh_law_misfit).
double median_misfit(const std::vector<std::optional<double>>& misfits) {
  std::vector<double> fitted;
  for (const std::optional<double>& m : misfits)
    if (m) fitted.push_back(*m);
  return fitted.empty() ? 1.0 : quantile(fitted, 0.5);
}

// One frame's sky-mask judgments on `sky` (whose dolp is that frame's), as StackSky::judgments makes
// them for every frame: from its E-vectors and its robust AoLP sun when it has the AoLP channel.
SkyJudgments judge_frame(const SkyImages& sky, const stack::Frame& frame, const camera::Camera& camera,
                         PolarizerModel polarizer_model) {
  const FrameRefs frames{&frame};
  const auto aolp = frame.channels.find("AoLP." + sky.band);
  std::vector<const FrameEVectors*> ev{nullptr};
  std::optional<FrameEVectors> e;
  if (aolp != frame.channels.end() && aolp->second.size() == sky.pixels()) {
    e.emplace(frame_e_vectors(sky, sky.dolp[0], aolp->second, camera.transport(), StackSky::kEVectorMinDolp,
                              polarizer_fit(frame, polarizer_model)));
    ev[0] = &*e;
  }
  if (!aolp_and_s0(sky, frames).first) return judge_sky(sky, frames, camera, SkyMaskParams{}, &ev, nullptr);
  double quality = 1.0;
  const std::vector<std::optional<Eigen::Vector3d>> suns{
      ev[0] ? sun_from_aolp(sky, sky.dolp[0], *ev[0], kMaskMinDolp, &quality, true) : std::nullopt};
  return judge_sky(sky, frames, camera, SkyMaskParams{}, &ev, &suns);
}

// rayleigh_law_misfit of the whole stack (sun_vector.h) where the mask leaves out pixels, from
// pass 3: per frame, the Rayleigh fit of the masked sky from the mask's sun, or from the lowest
// filtered DoLP of the unmasked sky.
double masked_misfit(const std::string& path, const std::string& dolp_name, SkyImages& unmasked, const SkyMask& mask,
                     std::size_t& retained, std::size_t kept_bytes) {
  const SkyImages& sky = unmasked;
  SkyImages masked = sky;
  apply_mask(masked, mask);
  const double radius = default_filter_radius_px(sky.width, sky.height);
  std::vector<std::optional<double>> misfits;
  (void)stack::read_stack_frames(path, {dolp_name}, [&](std::size_t t, stack::Frame&& frame) {
    const std::vector<float>& dolp = frame.channels.at(dolp_name);
    unmasked.dolp = FrameImages();
    unmasked.dolp.push_back(dolp);
    masked.dolp = unmasked.dolp;
    const std::optional<Eigen::Vector3d> start =
        mask.suns[t] ? mask.suns[t]
                     : find_suns(unmasked, std::vector<std::vector<float>>{disk_filter(dolp, unmasked, radius)}).front();
    misfits.push_back(frame_misfit(masked, start, true));
    retained = std::max(retained, sky_bytes(sky) + sky_bytes(masked) + mask.masked.capacity() +
                                      misfits.capacity() * sizeof(misfits[0]) + kept_bytes);
  });
  unmasked.dolp = FrameImages();
  return median_misfit(misfits);
}

}  // namespace

StreamedEstimate run_classic_streamed(const std::string& path, const InputOptions& input) {
  const auto started = std::chrono::steady_clock::now();
  const Method& method = method_entry("classic");
  ClassicParams params;
  params.input = input;
  const stack::StackSummary summary = stack::peek_stack(path);
  const std::vector<std::string> channels = estimator_channels(path, input);
  const std::string band = pick_band(summary.bands, summary.channels, input);
  const std::string dolp_name = "DoLP." + band;
  StreamedEstimate out;
  if (std::find(channels.begin(), channels.end(), dolp_name) == channels.end()) {
    // No such band: the estimator names what the stack holds, from the stack read whole (it is only
    // read to say so).
    out.stack = stack::read_stack(path, channels);
    out.estimate = run_method(out.stack, "classic", input);
    return out;
  }
  const std::size_t frames = static_cast<std::size_t>(summary.frames);
  const std::size_t min_frames = classic_min_frames(params);

  // Pass 1: the whole stack's valid pixels.
  std::optional<WholeSkyReader> reader;
  (void)stack::read_stack_frames(
      path, only(channels, {dolp_name, "mask", "clipped"}),
      [&](const stack::Stack& s) {
        out.stack = s;
        reader.emplace(out.stack, frames, input, min_frames, method.name);
      },
      [&](std::size_t, stack::Frame&& frame) {
        reader->add(frame);
        out.stack.frames.push_back(without_channels(frame));
        out.retained_bytes = std::max(out.retained_bytes, reader->bytes());
      });
  if (!reader) reader.emplace(out.stack, frames, input, min_frames, method.name);  // a stack of no parts
  SkyImages sky = reader->sky();
  reader.reset();
  out.passes = 1;

  // The runs: the whole stack's and the frame jackknife's (uncertainty.h frame_jackknife: frame i is
  // in group i mod k).
  const int n = static_cast<int>(frames);
  const int k = frame_jackknife_groups(n, method.traits.frame_jackknife_max_groups);
  std::vector<std::vector<std::uint8_t>> keeps{{}};
  for (int g = 0; g < k; ++g) {
    std::vector<std::uint8_t>& keep = keeps.emplace_back(frames);
    for (int i = 0; i < n; ++i) keep[static_cast<std::size_t>(i)] = i % k != g ? 1 : 0;
  }
  auto runs = std::make_shared<ClassicRuns>(sky, params, frames, keeps);

  // Pass 2: classic's filtered frames and pairs, the readings and the judgments, frame by frame.
  auto readings = std::make_shared<Readings>();
  if (input.sky_mask) readings->tally.emplace(sky.pixels());
  const camera::Camera& camera = *out.stack.camera;
  (void)stack::read_stack_frames(path, channels, [&](std::size_t, stack::Frame&& frame) {
    const std::vector<float>& dolp = frame.channels.at(dolp_name);
    sky.dolp = FrameImages();
    sky.dolp.push_back(dolp);
    std::optional<Eigen::Vector3d> sun;
    std::optional<SkyJudgments> judged;
    tbb::parallel_invoke([&] { runs->add(disk_filter(dolp, sky, runs->radius_px())); },
                         [&] { sun = find_suns(sky, sky.dolp).front(); },
                         [&] {
                           if (readings->tally) judged.emplace(judge_frame(sky, frame, camera, input.polarizer_model));
                         });
    readings->unread.push_back(unreadable_share(sky, 0, sun));
    readings->ring.push_back(ring_spread(sky, 0, sun));
    // The misfit's fit as if the mask left out nothing (a clear sky's), from the mask's sun or the
    // lowest filtered DoLP (classic's filter, when its radius is the fit's default).
    std::optional<Eigen::Vector3d> start;
    if (judged && judged->suns[0])
      start = judged->suns[0];
    else if (runs->radius_px() == default_filter_radius_px(sky.width, sky.height))
      start = runs->sun(readings->unread.size() - 1);
    else
      start = find_suns(sky, std::vector<std::vector<float>>{
                                 disk_filter(dolp, sky, default_filter_radius_px(sky.width, sky.height))})
                  .front();
    readings->unmasked_misfit.push_back(frame_misfit(sky, start, input.sky_mask));
    if (judged) readings->tally->add(*judged);
    out.retained_bytes = std::max(out.retained_bytes, sky_bytes(sky) + runs->bytes() + readings->bytes());
  });
  sky.dolp = FrameImages();
  out.passes = 2;

  MethodRun run;
  run.estimate = runs->answer(0);
  run.without_frames = [runs, keeps](const std::vector<std::uint8_t>& keep) {
    for (std::size_t r = 1; r < keeps.size(); ++r)
      if (keeps[r] == keep) return runs->answer(r);
    throw std::logic_error("run_classic_streamed: a frame jackknife's subset it did not run");
  };
  SkyReadings measured;
  UnreadableSky unread;
  for (const UnreadableSky& u : readings->unread) {
    unread.unpolarized += u.unpolarized;
    unread.clipped += u.clipped;
  }
  const auto count = static_cast<double>(readings->unread.size());
  measured.unread = sky.valid_count == 0 ? UnreadableSky{} : UnreadableSky{unread.unpolarized / count, unread.clipped / count};
  double ring_total = 0;
  int ring_frames = 0;
  for (const std::optional<double>& a : readings->ring)
    if (a) {
      ring_total += *a;
      ++ring_frames;
    }
  measured.ring_anisotropy = ring_frames ? ring_total / ring_frames : 0.0;
  measured.misfit = [&] {
    if (readings->tally) {
      const SkyMask mask = readings->tally->mask(sky);
      if (mask.masked_count > 0 && sky.valid_count - mask.masked_count >= 50) {  // apply_mask changes the sky
        ++out.passes;
        return masked_misfit(path, dolp_name, sky, mask, out.retained_bytes, runs->bytes() + readings->bytes());
      }
    }
    return median_misfit(readings->unmasked_misfit);
  };
  out.estimate = finish_method_run(out.stack, method, input, std::move(run), std::move(measured), started);
  return out;
}

}  // namespace skypol::skypole
