// Running estimators by name: run_method gives a method's answer on a stack with its stated
// uncertainty, after the calibration's gates, or auto's combination of them; what `skypol
// estimate`, `skypol evaluate`, the studies and the Python module call. This header also brings
// in the pieces of a dataset-level evaluation, one header each: auto's combination (auto.h), the
// gates (calibration_gates.h), the per-method statistics (evaluate_summary.h) and the CSV and text
// tables (evaluate_tables.h).
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "stack/frame.h"
#include "skypole/auto.h"
#include "skypole/calibration_gates.h"
#include "skypole/classic.h"
#include "skypole/estimate.h"
#include "skypole/evaluate_summary.h"
#include "skypole/evaluate_tables.h"
#include "skypole/method_registry.h"

namespace skypol::skypole {

// The methods are those of the registry (method_registry.h: method_names(), each entry's traits
// and calibration) and "auto" (the combination, auto.h).

// Runs the named method with its defaults and the given input options, then states its
// uncertainty (skypole/uncertainty.h: a frame-group jackknife, the method's calibration factor)
// and declines it, with the numbers, when its 95 % cone is wider than input.max_uncertainty_deg.
// Throws std::invalid_argument for an unknown name (listing the legal ones) or unusable input.
//
// "auto" runs every method the stack allows, each as above: a method that needs the site
// (sun_vector_ephemeris) only when the stack knows its site and times and the input does not
// withhold them (site_usable; an imported capture without [site] does not know them).
// Two answers agree when their angle is within 1.52 × the root-sum-square of their 95 % cones
// (the 99.9 % level); the answer most others agree with is the centre; of the agreeing group, auto
// returns the answer of a method whose traits say auto_answers_alone (sun_vector_ephemeris) as it
// stands when it is a member (an average with the others is less accurate), and otherwise the
// inverse-variance mean of the members' poles, stated with the σ of the sharpest member (the
// methods read the same frames, so their errors are correlated and the mean's own σ would claim
// more than the data hold). auto declines
// when no method answers, or when the agreeing group is no larger than the dissenting answers
// (the data do not decide); the note names the answer's method, the agreeing, the outvoted and
// the declined methods with their reasons.
// classic_images (method "classic" only): filled with classic's step images, from the same run.
PoleEstimate run_method(const stack::Stack& stack, std::string_view method,
                        const InputOptions& input = {}, ClassicImages* classic_images = nullptr);

// What run_method measures of a stack's sky for a method's gates and σ terms, given by a caller
// that measured it itself (a stack read frame by frame: classic_stream.h): the Rayleigh-law
// misfit, asked for only when the answer needs it (rayleigh_law_misfit), the unreadable shares
// (unreadable_sky) and the ring anisotropy (ring_anisotropy). What is missing is measured from
// the stack, as run_method would.
struct SkyReadings {
  std::function<double()> misfit;
  std::optional<UnreadableSky> unread;
  std::optional<double> ring_anisotropy;
};
// run_method's steps after the method's own run: the misfit, the gates, the jackknives (from
// run.without_frames and run.without_sector) and the calibrated uncertainty, for a caller that ran
// the method itself, on `stack`, whose frames need hold no channel when `readings` and `run` have
// all the gates and jackknives read. `started`: when the run began (PoleEstimate::seconds).
PoleEstimate finish_method_run(const stack::Stack& stack, const Method& method, const InputOptions& input,
                               MethodRun run, SkyReadings readings, std::chrono::steady_clock::time_point started);

// run_method, but for "auto" when `done` already holds an answer of every method auto weighs:
// combine_estimates of them, running nothing again (`-m all`, evaluate, the studies).
PoleEstimate run_or_combine(const stack::Stack& stack, std::string_view method, const InputOptions& input,
                            const std::vector<PoleEstimate>& done);

}  // namespace skypol::skypole
