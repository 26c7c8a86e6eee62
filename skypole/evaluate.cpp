// Running estimators by name (evaluate.h): a method's answer with its gates and its stated
// uncertainty, and auto's run of every method it weighs.
#include "skypole/evaluate.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>

#include "skypole/auto.h"
#include "skypole/calibration_gates.h"
#include "skypole/classic.h"
#include "skypole/cloud_share.h"
#include "skypole/run_bare.h"
#include "skypole/stack_sky.h"
#include "skypole/sun_vector.h"
#include "skypole/uncertainty.h"

namespace skypol::skypole {
namespace {

// What the methods of one stack share, made once: its prepared sky, mask judgments and E-vectors
// (stack_sky.h, read by every method and its jackknives' sub-runs), and the measures of the sky the
// calibration reads (the Rayleigh-law misfit, the unreadable shares), which auto's methods would
// each measure again.
struct SharedWork {
  SharedWork(const stack::Stack& stack, const InputOptions& input) : whole(stack, input) {}
  StackSky whole;
  std::optional<double> misfit;         // rayleigh_law_misfit of the whole stack
  std::function<double()> measure_misfit;  // how, when not that (SkyReadings::misfit)
  std::optional<UnreadableSky> unread;  // unreadable_sky of its sky
  std::optional<double> ring;           // ring_anisotropy of its sky
};

// run_method's steps after the method's own run, `run`, on `work`'s stack.
PoleEstimate finish_run(SharedWork& work, const Method& method, MethodRun run,
                        std::chrono::steady_clock::time_point t0) {
  const StackSky& whole = work.whole;
  const stack::Stack& stack = whole.stack();
  const InputOptions& input = whole.input();
  const MethodTraits& traits = method.traits;
  PoleEstimate e = std::move(run.estimate);
  if (!e.valid) return e;
  // A sky far from Rayleigh's law bends what the methods that read its shape find, alike in every
  // frame and sector (method_registry.h misfit_measured; each entry says why): measured once per
  // stack for their gates and σ terms.
  if (traits.misfit_measured) {
    if (!work.misfit) work.misfit = work.measure_misfit ? work.measure_misfit() : rayleigh_law_misfit(SkyView(whole));
    e.model_misfit = *work.misfit;
  }
  const MethodCalibration& cal = method.calibration;
  std::optional<UnreadableSky>& unread = work.unread;  // the sky's unpolarized and clipped shares, once measured
  apply_calibration_gates(e, cal, whole, unread, work.ring);
  if (!e.valid) return e;
  const int frame_count = static_cast<int>(stack.frames.size());
  const int max_groups = traits.frame_jackknife_max_groups;
  if (!run.without_frames)
    run.without_frames = [&](const std::vector<std::uint8_t>& keep) {
      return method.bare(SkyView::kept(whole, keep));
    };
  const std::optional<Eigen::Matrix2d> frames = frame_jackknife(e, frame_count, run.without_frames, max_groups);
  if (!frames) return e;
  Jackknives jack;
  jack.frames = *frames;
  jack.frame_groups = frame_jackknife_groups(frame_count, max_groups);
  if (traits.sector_jackknife && run.sectors) {
    // Sectors about the principal point, so that each holds a sixth of the sky (invariance: about
    // its pole, within the window it reads).
    const camera::Intrinsics& k = stack.camera->lens().intrinsics();
    if (!run.without_sector)
      run.without_sector = [&](int g) {
        return method.bare(SkyView::without_sector(whole, Eigen::Vector2d(k.cx, k.cy), g, kSkySectors));
      };
    const auto s = sector_jackknife(e, kSkySectors, run.without_sector);
    if (!s) return e;
    jack.sectors = *s;
    jack.sector_groups = kSkySectors;
  }
  if (input.calibrated) {
    // The σ terms' readings (uncertainty.h calibrated_covariance); the sky's shares are measured
    // only when a term reads them (or a gate measured them already).
    CalibrationReadings r;
    r.residual_deg = e.residual_deg;
    r.pixel_deg = pixel_angle_deg(*stack.camera);
    if (reads_unreadable_sky(cal) && !unread) unread = unreadable_sky(whole.sky(1, e.method));
    r.unpolarized_share = unread ? unread->unpolarized : 0.0;
    r.clipped_share = unread ? unread->clipped : 0.0;
    r.sun_elevation_misfit_deg = e.sun_elevation_misfit_deg;
    r.model_misfit = e.model_misfit;
    set_stated_uncertainty(e, jack, calibrated_covariance(cal, jack, r));
  } else {
    // Uncalibrated (what the calibration study measures the factors from).
    set_stated_uncertainty(e, jack, uncalibrated_covariance(jack));
  }
  apply_uncertainty_bound(e, input.max_uncertainty_deg);
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return e;
}

// run_method of one method on `work`'s stack.
PoleEstimate run_with(SharedWork& work, const Method& method, ClassicImages* classic_images) {
  const StackSky& whole = work.whole;
  const auto t0 = std::chrono::steady_clock::now();
  check_site(method, whole.stack(), whole.input());
  // The method's answer, with what its jackknives refit from its own work (method_registry.h
  // MethodRun); the refits it does not give rerun its bare run on a view of the stack.
  MethodRun run;
  if (method.run)
    run = method.run(whole, classic_images);
  else
    run.estimate = method.bare(SkyView(whole));
  return finish_run(work, method, std::move(run), t0);
}

// auto: every method it weighs, on one SharedWork (a method that throws is a declined answer),
// then their combination.
PoleEstimate run_auto(const stack::Stack& stack, const InputOptions& input) {
  std::vector<PoleEstimate> all;
  SharedWork work(stack, input);
  const bool site = site_usable(stack, input);
  for (const Method& m : methods()) {
    if (!used_by_auto(m.name, site)) continue;
    PoleEstimate e;
    try {
      e = run_with(work, m, nullptr);
    } catch (const std::invalid_argument& err) {
      e = PoleEstimate{};
      e.method = m.name;
      e.why_invalid = err.what();
    }
    all.push_back(std::move(e));
  }
  return combine_estimates(stack, input, all);
}

}  // namespace

PoleEstimate run_method(const stack::Stack& stack, std::string_view method,
                        const InputOptions& input, ClassicImages* classic_images) {
  if (method == "auto") return run_auto(stack, input);
  const Method& m = method_entry(method);
  SharedWork work(stack, input);
  return run_with(work, m, classic_images);
}

PoleEstimate finish_method_run(const stack::Stack& stack, const Method& method, const InputOptions& input,
                               MethodRun run, SkyReadings readings, std::chrono::steady_clock::time_point started) {
  SharedWork work(stack, input);
  work.measure_misfit = std::move(readings.misfit);
  work.unread = readings.unread;
  work.ring = readings.ring_anisotropy;
  check_site(method, stack, input);
  return finish_run(work, method, std::move(run), started);
}

PoleEstimate run_or_combine(const stack::Stack& stack, std::string_view method, const InputOptions& input,
                            const std::vector<PoleEstimate>& done) {
  const bool site = site_usable(stack, input);
  const auto computed = [&](const Method& m) {
    return !used_by_auto(m.name, site) ||
           std::any_of(done.begin(), done.end(), [&](const PoleEstimate& d) { return d.method == m.name; });
  };
  if (method == "auto" && std::all_of(methods().begin(), methods().end(), computed))
    return combine_estimates(stack, input, done);
  return run_method(stack, method, input);
}

}  // namespace skypol::skypole
