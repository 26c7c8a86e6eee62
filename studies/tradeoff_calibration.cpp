// Study: are the stated uncertainties honest? A seeded random population of scenes unlike the
// shipped ones (tradeoff_calibration.h: the mixed, realistic and mismatch populations) — sites
// from the equator to high latitudes, dates through the year, windows of 20 min to 12 h with a
// frame every 2–30 min, any heading, tilts up to 15°, every analytic lens model, the mono or
// colour DoFP sensor at various exposures and gains (or none), 0–50 % cloud, the Rayleigh, Berry
// and multiple-scattering (vrte) skies — each rendered small (binning 8: 306×256; --small:
// binning 16, 153×128) and given to every method and to auto, with --max-uncertainty (default
// 2.5°: StudyOptions). Per stack and method: the error against the truth, the stated σ and 95 %
// cone. Per method: the yield (share of valid answers), the lie rate (valid with error > 5°, or
// > 5σ), the coverage (share of valid answers whose 95 % cone holds the truth, with its 95 %
// Wilson interval), the error distribution, and the σ factor that would have made the coverage
// exactly 95 % (what scripts/calibration_tune.py reads each method's MethodCalibration,
// skypole/uncertainty.h, off, from --uncalibrated runs; docs/benchmarks.md section 7 says how, and
// docs/calibration-history.md which runs). The same per sky model (calibration_by_sky.csv),
// and auto against each method on the scenes both answer (calibration_auto.csv).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <stdexcept>

#include "sky/units.h"
#include "skypole/cloud_share.h"
#include "skypole/estimate.h"
#include "skypole/evaluate.h"
#include "skypole/sky_images.h"
#include "skypole/uncertainty.h"
#include "studies/tradeoff_calibration.h"
#include "studies/tradeoff_studies.h"
#include "studies/tradeoff_table.h"

namespace skypol::studies::tradeoff {
namespace {

constexpr double kLieDeg = 5.0;    // an answer this far off, while valid, is a lie
constexpr double kLieSigma = 5.0;  // … or this many of its own σ off

using calibration::Draw;
using calibration::Outcome;

// calibration.csv: one row per (scene, method). The scene's draw, the answer and its score, the
// raw jackknives, and last the mismatch population's own draws.
Table calibration_rows() {
  return Table({"stack", "seed", "latitude_deg", "longitude_deg", "date", "window_min", "step_min", "frames",
                "heading_deg", "tilt_deg", "lens", "sky", "max_dolp", "aerosol", "tau_550", "ground_albedo", "cloud",
                "sensor", "exposure_us", "auto_exposure", "gain_factor", "binning", "pixel_deg", "method", "valid",
                "why_invalid", "angular_error_deg", "bearing_error_deg", "latitude_error_deg", "sigma_bearing_deg",
                "sigma_latitude_deg", "sigma_deg", "cone95_deg", "inside_cone", "lie", "residual_deg", "model_misfit",
                "sun_elevation_misfit_deg", "unpolarized_share", "clipped_share", "ring_anisotropy", "pole_x",
                "pole_y", "pole_z", "is_north", "offset_az_deg", "offset_alt_deg", "sigma_frames_deg",
                "frame_groups", "sigma_sectors_deg", "frames_aa_deg2", "frames_ab_deg2", "frames_bb_deg2",
                "sectors_aa_deg2", "sectors_ab_deg2", "sectors_bb_deg2", "estimate_s", "median_radius_um",
                "geometric_std", "refractive_real", "refractive_imag", "angstrom", "ssa", "streams", "grid",
                "separation_deg", "berry_normalisation", "angle_error_max_deg", "extinction_ratio", "prnu_rms",
                "dsnu_e"});
}

// The methods (all, or a subset in the order given, checked by the command line), then auto over
// them twice: with the site where the stack knows it, and site-free (as `--site unknown`), last.
std::vector<std::string> calibration_methods(const StudyOptions& o) {
  std::vector<std::string> methods = o.methods;
  if (methods.empty())
    for (const skypole::Method& m : skypole::methods()) methods.push_back(m.name);
  methods.push_back("auto");
  methods.push_back(skypole::kAutoSiteFree);
  return methods;
}

skypole::InputOptions calibration_input(const StudyOptions& o) {
  skypole::InputOptions input;
  input.max_uncertainty_deg = o.max_uncertainty_deg;
  input.calibrated = !o.uncalibrated;
  input.cloud_gate = !o.no_cloud_gate;
  input.sky_mask = !o.no_sky_mask;
  return input;
}

// The cloud gate's measures (skypole/cloud_share.h), written for every row so that its threshold
// can be read off this table; undefined (empty) for a stack with no usable sky pixel (a sensor
// clipped everywhere), which every method then declines.
struct SkyMeasures {
  double unpolarized = std::nan(""), clipped = std::nan(""), anisotropy = std::nan("");
};

SkyMeasures sky_measures(const stack::Stack& stack, const skypole::InputOptions& input) {
  SkyMeasures m;
  try {
    const skypole::SkyImages sky = skypole::prepare_sky_images(stack, input, 1, "calibration");
    const skypole::UnreadableSky unread = skypole::unreadable_sky(sky);
    m.unpolarized = unread.unpolarized;
    m.clipped = unread.clipped;
    m.anisotropy = skypole::ring_anisotropy(sky);
  } catch (const std::invalid_argument&) {
    // no usable sky pixel: the measures stay undefined
  }
  return m;
}

// One method's answer on the stack; auto and auto_site_free combine the answers already `done`. A
// stack the method cannot take (std::invalid_argument) is an invalid answer with the reason.
skypole::PoleEstimate estimate(const stack::Stack& stack, const std::string& method, const skypole::InputOptions& input,
                               const std::vector<skypole::PoleEstimate>& done) {
  try {
    if (method == "auto") return skypole::combine_estimates(stack, input, done);
    if (method == skypole::kAutoSiteFree) {
      skypole::InputOptions site_free = input;
      site_free.use_site = false;
      return skypole::combine_estimates(stack, site_free, done);
    }
    return skypole::run_method(stack, method, input);
  } catch (const std::invalid_argument& err) {
    skypole::PoleEstimate e;
    e.method = method;
    e.why_invalid = err.what();
    return e;
  }
}

// The row's scene columns: the draw as rendered (a metered exposure is frame 0's).
void set_scene(Table& rows, const Draw& d, const stack::Stack& stack, const StudyOptions& o, int binning,
               const SkyMeasures& measures) {
  rows.set("stack", d.index)
      .set("seed", static_cast<int>(o.seed))
      .set("latitude_deg", d.site.latitude_deg)
      .set("longitude_deg", d.site.longitude_deg)
      .set("date", d.date)
      .set("window_min", d.window_min)
      .set("step_min", d.step_min)
      .set("frames", d.frames)
      .set("heading_deg", d.heading)
      .set("tilt_deg", d.tilt)
      .set("lens", d.lens)
      .set("sky", d.sky_model)
      .set("max_dolp", d.max_dolp)
      .set("aerosol", d.aerosol)
      .set("tau_550", d.tau_550)
      .set("ground_albedo", d.ground_albedo)
      .set("pixel_deg", skypole::pixel_angle_deg(*stack.camera))
      .set("cloud", d.cloud)
      .set("sensor", d.sensor)
      .set("exposure_us", d.auto_exposure ? stack.frames.front().exposure_us.value_or(0) : d.exposure_us)
      .set("auto_exposure", d.auto_exposure)
      .set("gain_factor", d.gain_factor)
      .set("binning", binning)
      .set("unpolarized_share", measures.unpolarized)
      .set("clipped_share", measures.clipped)
      .set("ring_anisotropy", measures.anisotropy);
}

// The mismatch population's draws (empty for the others, which keep the defaults): the aerosol's
// optics and the solver's settings on a vrte sky, the neutral points on a Berry sky, the sensor's
// manufacturing errors.
void set_off_family(Table& rows, const Draw& d) {
  if (!d.off_family) return;
  if (d.sky_model == "vrte") {
    const sky::AerosolSpec& a = d.aerosol_optics;
    if (d.aerosol == "custom")
      rows.set("median_radius_um", a.median_radius_um)
          .set("geometric_std", a.geometric_std)
          .set("refractive_real", a.refractive_real)
          .set("refractive_imag", a.refractive_imag);
    if (a.angstrom) rows.set("angstrom", *a.angstrom);
    if (a.ssa) rows.set("ssa", *a.ssa);
    rows.set("streams", d.streams).set("grid", d.grid);
  }
  if (d.sky_model == "berry")
    rows.set("separation_deg", d.separation_deg).set("berry_normalisation", d.berry_normalisation);
  double worst = 0;
  for (const double a : d.angle_error_deg) worst = std::max(worst, std::abs(a));
  rows.set("angle_error_max_deg", worst)
      .set("extinction_ratio", d.extinction_ratio)
      .set("prnu_rms", d.prnu_rms)
      .set("dsnu_e", d.dsnu_e);
}

// A valid answer scored against frame 0's truth: its error, σ and cone, whether the cone holds the
// truth and whether it lies, into the row and the outcome the summaries read.
void score_answer(Table& rows, Outcome& out, const Draw& d, const stack::Stack& stack, const skypole::PoleEstimate& e) {
  const skypole::Score s = skypole::score(e, stack.frames.front().truth);
  const bool inside = s.angular_error_deg <= e.cone95_deg;
  const bool lie = s.angular_error_deg > kLieDeg || s.angular_error_deg > kLieSigma * e.sigma_deg;
  out.valid = true;
  out.inside = inside;
  out.lie = lie;
  out.error = s.angular_error_deg;
  out.ratio = e.cone95_deg > 0 ? s.angular_error_deg / e.cone95_deg : 1e9;
  rows.set("angular_error_deg", s.angular_error_deg)
      .set("latitude_error_deg", std::abs(s.latitude_error_deg))
      .set("sigma_bearing_deg", e.sigma_bearing_deg)
      .set("sigma_latitude_deg", e.sigma_latitude_deg)
      .set("sigma_deg", e.sigma_deg)
      .set("cone95_deg", e.cone95_deg)
      .set("inside_cone", inside)
      .set("lie", lie)
      .set("residual_deg", e.residual_deg)
      .set("model_misfit", e.model_misfit)
      .set("sun_elevation_misfit_deg", e.sun_elevation_misfit_deg)
      .set("pole_x", e.pole_level.x())
      .set("pole_y", e.pole_level.y())
      .set("pole_z", e.pole_level.z())
      .set("is_north", e.is_north);
  // The raw jackknife covariances (uncertainty.h; deg², axes azimuth and altitude), so that
  // scripts/calibration_tune.py can try any factors on them without running anything again.
  const double d2 = 1.0 / (kRadPerDeg * kRadPerDeg);
  const Eigen::Matrix2d& cf = e.jackknife_frames_rad2;
  const Eigen::Matrix2d& cs = e.jackknife_sectors_rad2;
  // The answer's offset from the true NCP in the tangent plane there (azimuth and altitude axes of
  // the level frame, degrees): with it an average of answers can be scored to the digit, which
  // the 6-digit truth columns cannot do for errors of 0.001°.
  skypole::PoleEstimate truth_pole;
  {
    const double h = -d.heading * kRadPerDeg, lat = d.site.latitude_deg * kRadPerDeg;
    truth_pole.pole_level = Eigen::Vector3d(std::sin(h) * std::cos(lat), std::cos(h) * std::cos(lat), std::sin(lat));
    truth_pole.is_north = true;
  }
  const Eigen::Vector2d off = skypole::tangent_offset(truth_pole, e) / kRadPerDeg;
  rows.set("offset_az_deg", off.x()).set("offset_alt_deg", off.y());
  rows.set("sigma_frames_deg", skypole::sigma_deg_of(cf))
      .set("frame_groups", e.jackknife_frame_groups)
      .set("sigma_sectors_deg", skypole::sigma_deg_of(cs))
      .set("frames_aa_deg2", cf(0, 0) * d2)
      .set("frames_ab_deg2", cf(0, 1) * d2)
      .set("frames_bb_deg2", cf(1, 1) * d2)
      .set("sectors_aa_deg2", cs(0, 0) * d2)
      .set("sectors_ab_deg2", cs(0, 1) * d2)
      .set("sectors_bb_deg2", cs(1, 1) * d2);
  if (s.bearing_error_deg) rows.set("bearing_error_deg", std::abs(*s.bearing_error_deg));
}

}  // namespace

int calibration_count(const StudyOptions& o) { return o.count > 0 ? o.count : (o.small ? 6 : 300); }

void check_calibration_scenes(const StudyOptions& o) {
  const int count = calibration_count(o);
  for (int k : o.scenes)
    if (k < 0 || k >= count)
      throw std::invalid_argument("tradeoff calibration: --scenes " + std::to_string(k) +
                                  " is not a scene of this run (0 to " + std::to_string(count - 1) + ")");
}

void study_calibration(const StudyOptions& o) {
  const int binning = o.binning > 0 ? o.binning : o.small ? 16 : 8;
  const int count = calibration_count(o);
  check_calibration_scenes(o);
  const calibration::Population& pop = calibration::population_of(o.population);
  std::mt19937_64 rng(o.seed);
  Table rows = calibration_rows();
  std::vector<Outcome> outcomes;  // one per (scene, method), for the summaries
  const std::vector<std::string> methods = calibration_methods(o);
  const skypole::InputOptions input = calibration_input(o);
  const auto chosen = [&](int k) { return o.scenes.empty() || std::ranges::find(o.scenes, k) != o.scenes.end(); };
  const std::filesystem::path partial = std::filesystem::path(o.out_dir) / "calibration.partial.csv";
  int scenes_run = 0;
  for (int k = 0; k < count; ++k) {
    const Draw d = calibration::draw_scene(rng, k, pop);  // drawn even when not chosen: the next scenes stay the same
    if (!chosen(k)) continue;
    const stack::Stack stack = calibration::render_draw(d, binning, o.noise_draw, pop);
    const SkyMeasures measures = sky_measures(stack, input);
    std::vector<skypole::PoleEstimate> done;
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const skypole::PoleEstimate e = estimate(stack, methods[m], input, done);
      done.push_back(e);
      rows.row();
      set_scene(rows, d, stack, o, binning, measures);
      rows.set("method", methods[m]).set("valid", e.valid).set("estimate_s", e.seconds);
      set_off_family(rows, d);
      Outcome out;
      out.method = m;
      out.stack = k;
      out.sky = d.sky_model;
      if (e.valid) score_answer(rows, out, d, stack, e);
      else rows.set("why_invalid", e.why_invalid);
      outcomes.push_back(out);
    }
    if (o.progress) std::fprintf(stderr, "calibration %d/%d\n", k + 1, count);
    // A run of hundreds of scenes takes minutes to hours: its rows so far, every 10 scenes, under a
    // name that says they are not the whole run (removed when calibration.csv is written).
    if (++scenes_run % 10 == 0) rows.write(partial.string());
  }
  rows.write((std::filesystem::path(o.out_dir) / "calibration.csv").string());
  std::filesystem::remove(partial);
  calibration::write_summaries(outcomes, methods, o, binning);
}

}  // namespace skypol::studies::tradeoff
