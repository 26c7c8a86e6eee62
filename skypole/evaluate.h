// Dataset-level evaluation: run estimators by name, score many (estimate, truth) rows, summarise
// them per method (mean, median, p95, max of |error|) and write CSV text for `skypol evaluate`.
// Statistics: over the valid rows only (an invalid estimate is counted, not scored); the median of
// an even count is the mean of the two middle values; p95 is the nearest-rank percentile
// (the ⌈0.95·n⌉-th smallest). CSV: RFC 4180 quoting, '.' decimals, an undefined value (bearing at
// a geographic pole, any error of an invalid row) is an empty field — never NaN.
#pragma once

#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "stack/frame.h"
#include "skypole/classic.h"
#include "skypole/estimate.h"
#include "skypole/method_registry.h"

namespace skypol::skypole {

// The methods are those of the registry (method_registry.h: method_names(), each entry's traits
// and calibration) and "auto" (the combination below).

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

// auto's combination of answers already computed by run_method (e.g. by `-m all`), without
// running anything again; only the methods used_by_auto(method, site_usable(stack, input)) are
// considered.
PoleEstimate combine_estimates(const stack::Stack& stack, const InputOptions& input,
                               const std::vector<PoleEstimate>& estimates);
// Whether auto weighs `method`'s answer: a registered method whose entry says so and that needs no
// site unless `site_usable`.
bool used_by_auto(std::string_view method, bool site_usable);
// The studies' label for auto's answer with the site withheld (InputOptions::use_site = false:
// site-free, as `--site unknown`), beside "auto", which uses the site where the stack knows it.
inline constexpr const char* kAutoSiteFree = "auto_site_free";
// run_method, but for "auto" when `done` already holds an answer of every method auto weighs:
// combine_estimates of them, running nothing again (`-m all`, evaluate, the studies).
PoleEstimate run_or_combine(const stack::Stack& stack, std::string_view method, const InputOptions& input,
                            const std::vector<PoleEstimate>& done);

// The gates of `c` on a valid answer `e` of a method on `stack` (run_method applies its own
// method's): declines `e` with the gate's reason and numbers. Nothing when !input.calibrated.
void apply_calibration_gates(PoleEstimate& e, const MethodCalibration& c, const stack::Stack& stack,
                             const InputOptions& input);

struct EvaluationRow {
  std::string dataset;    // e.g. the stack's file name
  PoleEstimate estimate;  // estimate.method names the method
  scene::Truth truth;    // the stack's truth (frame 0)
};

struct Stats {
  int n = 0;
  double mean = 0, median = 0, p95 = 0, max = 0;
};
Stats summarize_values(std::vector<double> values);  // n = 0 and zeros for no values

struct MethodSummary {
  std::string method;
  int rows = 0;
  int valid = 0;
  Stats bearing_abs_deg;   // over the valid rows with a defined bearing
  Stats latitude_abs_deg;
  Stats angular_deg;
  double mean_seconds = 0;  // over all rows
};

// One summary per method, in order of first appearance.
std::vector<MethodSummary> summarize(const std::vector<EvaluationRow>& rows);

// Columns: dataset,method,valid,why_invalid,heading_deg,latitude_deg,azimuth_rel_deg,altitude_deg,
// is_north,true_heading_deg,true_latitude_deg,bearing_error_deg,latitude_error_deg,
// angular_error_deg,residual_deg,sigma_bearing_deg,sigma_latitude_deg,cone95_deg,sigma_deg,
// seconds,note
std::string rows_csv(const std::vector<EvaluationRow>& rows);
// Columns: method,rows,valid,{bearing,latitude,angular}_{n,mean,median,p95,max},mean_seconds
std::string summary_csv(const std::vector<MethodSummary>& summaries);
// One CSV field, quoted as RFC 4180 asks when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& s);
// A fixed-width table for a terminal.
std::string summary_text(const std::vector<MethodSummary>& summaries);

}  // namespace skypol::skypole
