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

namespace skypol::skypole {

// "classic", "great_circle", "invariance", "sun_vector" (AoLP, circle), "sun_vector_ephemeris"
// (AoLP, ephemeris), "sun_dolp" (Rayleigh fit of DoLP, circle), "auto" (the combination below).
const std::vector<std::string>& method_names();

// Runs the named method with its defaults and the given input options, then states its
// uncertainty (skypole/uncertainty.h: a frame-group jackknife, the method's calibration factor)
// and declines it, with the numbers, when its 95 % cone is wider than input.max_uncertainty_deg.
// Throws std::invalid_argument for an unknown name (listing the legal ones) or unusable input.
//
// "auto" runs every method the stack allows, each as above: sun_vector_ephemeris only when the
// stack knows its site and times (stack.site_known; an imported capture without [site] does not).
// Two answers agree when their angle is within 1.52 × the root-sum-square of their 95 % cones
// (the 99.9 % level); the answer most others agree with is the centre; of the agreeing group, auto
// returns sun_vector_ephemeris' answer as it stands when it is a member (an average with the
// others was less accurate), and otherwise the inverse-variance mean of the members' poles, stated
// with the σ of the sharpest member (the methods read the same frames, so their errors are
// correlated and the mean's own σ would claim more than the data hold). auto declines
// when no method answers, or when the agreeing group is no larger than the dissenting answers
// (the data do not decide); the note names the answer's method, the agreeing, the outvoted and
// the declined methods with their reasons.
// classic_images (method "classic" only): filled with classic's step images, from the same run.
PoleEstimate run_method(const stack::Stack& stack, std::string_view method,
                        const InputOptions& input = {}, ClassicImages* classic_images = nullptr);

// auto's combination of answers already computed by run_method (e.g. by `-m all`), without
// running anything again; only the methods used_by_auto(method, stack.site_known) are considered.
PoleEstimate combine_estimates(const stack::Stack& stack, const InputOptions& input,
                               const std::vector<PoleEstimate>& estimates);
bool used_by_auto(std::string_view method, bool site_known);

// A method's calibration (skypole/uncertainty.h), measured by the calibration study: since section
// 7l on seeds 1, 3–12 and 26 at binning 16 and 3, 4, 5, 21 and 27 at binning 8, rendered with the
// clipped sky masked (invariance: 7k's with a higher floor); before it on seeds 1 and 3–12
// (docs/calibration-history.md, sections 7a and 7c–7l). The stated covariance is
//     C = w²·(inflation²·C_frames + b²·C_sectors) + s²·I,
//     b = sector_inflation + sector_unpolarized·unpolarized_share + sector_clipped·clipped_share
// (w²: the widening for the jackknives' few groups, uncertainty.h few_groups_widening2)
//     s² = floor_deg² + (residual_share·max(0, residual_deg − residual_pixels·pixel))²
//          + (unpolarized_deg·unpolarized_share)² + (elevation_share·sun_elevation_misfit_deg)²
//          + (misfit_deg·model_misfit)²
// (pixel: pixel_angle_deg of the stack's camera, uncertainty.h; the shares: cloud_share.h unreadable_sky)
// — the frame jackknife sees errors that differ between frames, the sector jackknife errors that
// live in one part of the sky in every frame, the unpolarized term how much of the sky a clear sky
// cannot explain, the floor the bias left (a sky unlike the method's model), the residual term a
// method whose own fit spreads (classic's blob at low resolution). Gates: where the study found the method's error unpredictable — a fit
// residual above max_residual_deg, a window shorter than min_window_min, a sky more than
// max_unpolarized_share unpolarized (cloud; skypole/cloud_share.h) — it declines, saying so.
struct MethodCalibration {
  std::string method;
  double inflation = 1.0;
  double floor_deg = 0.0;
  double residual_share = 0.0;
  double max_residual_deg = std::numeric_limits<double>::infinity();
  double min_window_min = 0.0;
  double max_unpolarized_share = std::numeric_limits<double>::infinity();
  double residual_pixels = 0.0;  // the residual term counts residual_deg − this many pixel angles (≥ 0)
  // Decline a sky whose DoLP is not a function of the angle to the sun beyond this
  // (ring_anisotropy, skypole/cloud_share.h: neutral points moved by a real sky).
  double max_ring_anisotropy = std::numeric_limits<double>::infinity();
  // Decline a sky that departs from the method's own model beyond this (PoleEstimate::model_misfit).
  double max_model_misfit = std::numeric_limits<double>::infinity();
  // Decline a sky more than this share clipped by the sensor in some frame (clipped_share,
  // cloud_share.h), beyond which the method's calibration holds no answer: invariance, whose σ has
  // no term for the sky it lost, was 0.065° off at 6.8σ on a clear sky 78 % clipped (section 7k;
  // the searches of 7l found no term that held on held-out seeds).
  double max_clipped_share = std::numeric_limits<double>::infinity();
  // The factor on the sector jackknife's covariance (uncertainty.h; 0: not counted), and a σ term
  // unpolarized_deg·unpolarized_share (cloud_share.h: cloud, neutral points, saturation — errors
  // every frame shares, which neither jackknife sees in full).
  double sector_inflation = 0.0;
  double unpolarized_deg = 0.0;
  // The sector factor grows by this per unit of unpolarized share. A cloud's error is shared by every
  // frame (the cloud stands still) but not by every part of the sky, so under cloud the sector
  // jackknife measures a bias, where on a clear sky its spread overstates the error (hence factors
  // under 1). great_circle at binning 8 answered 2.82° off at 6.6σ on a sky 52 % unpolarized whose
  // raw sector jackknife said 0.99°; sun_vector_ephemeris' tuning seeds covered 0.996 of their clear
  // skies' truths and 0.951 of those 15–30 % unpolarized (section 7h).
  double sector_unpolarized = 0.0;
  // The sector factor grows by this per unit of clipped share (UnreadableSky::clipped): a sky whose
  // sun side the sensor masked leaves the six sectors unequal, so that their spread can understate
  // the error. great_circle took it in section 7l (its coverage on partly clipped skies at binning 8
  // was 0.882 on seeds 21 and 27); since its delete-one frame jackknife (7m) no committed
  // calibration needs it (great_circle covers 0.923 of its 52 partly clipped tuning answers
  // without it), and the searches keep offering it.
  double sector_clipped = 0.0;
  // A σ term elevation_share·sun_elevation_misfit_deg (PoleEstimate: the shared error of the
  // ephemeris' suns that their elevations show and no jackknife resolves).
  double elevation_share = 0.0;
  // A σ term misfit_deg·model_misfit, degrees per unit of misfit (PoleEstimate::model_misfit: how far
  // the sky departs from Rayleigh's law; a multiply scattering sky moves the suns a method finds
  // alike in every frame and sector, so that neither jackknife sees it, by more the further it
  // departs). 0: not counted.
  double misfit_deg = 0.0;
};
// Whether `method` runs the sector jackknife (uncertainty.h): the methods that fit the whole sky
// per frame (sun_vector, sun_vector_ephemeris, sun_dolp); great_circle, which refits its pairs'
// cached zero crossings outside each sector rather than rerunning (great_circle.h); and invariance,
// which refits its co-rotating window about the pole without each sector of that window (a masked
// wedge of the whole sky would trip its edge checks; invariance.h). classic stays the paper's.
bool has_sector_jackknife(std::string_view method);
// The most frame groups `method`'s frame jackknife deals its frames into (uncertainty.h
// frame_jackknife). A jackknife's variance is itself estimated from K − 1 degrees of freedom, so
// few groups state a σ that is often far too small: even when right on average, an error beyond 5
// stated σ (a lie) is then a tail of F(2, K − 1) — 0.27 % of answers at K = 6, 0.018 % at K = 18
// (uncertainty.h, "Few groups"). great_circle refits only its pole from cached circles (great_circle.h),
// so it deletes one frame at a time, up to 24: on held-out seed 2's scene 9 at binning 8 (19 frames,
// mono sensor), seven draws of the noise gave errors of 0.09–0.53° and raw frame σs of 0.07–0.49°
// with 6 groups, 0.13–0.41° with 19 (docs/benchmarks.md, section 7m). The others rerun the
// whole method per group and keep 6.
int frame_jackknife_max_groups(std::string_view method);
const std::vector<MethodCalibration>& method_calibrations();

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
