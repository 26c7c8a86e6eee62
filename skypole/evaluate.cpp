// Scoring many rows and writing them out (evaluate.h).
#include "skypole/evaluate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "sky/units.h"
#include "skypole/classic.h"
#include "skypole/cloud_share.h"
#include "skypole/run_bare.h"
#include "skypole/sky_images.h"
#include "skypole/stack_sky.h"
#include "skypole/sun_vector.h"
#include "skypole/uncertainty.h"

namespace skypol::skypole {
namespace {


std::string num(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream os;
  os << std::setprecision(10) << v;
  return os.str();
}

std::string num(const std::optional<double>& v) { return v ? num(*v) : std::string(); }

}  // namespace

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

namespace {

double angle_deg(const PoleEstimate& a, const PoleEstimate& b) {
  return deg_from_rad(tangent_offset(a, b).norm());
}

}  // namespace

bool used_by_auto(std::string_view method, bool site_usable) {
  const Method* m = find_method(method);
  return m && m->traits.used_by_auto && (!m->traits.needs_site || site_usable);
}

PoleEstimate combine_estimates(const stack::Stack& stack, const InputOptions& input,
                               const std::vector<PoleEstimate>& estimates) {
  std::vector<PoleEstimate> all;
  double total_seconds = 0;
  const bool site = site_usable(stack, input);
  for (const PoleEstimate& e : estimates)
    if (used_by_auto(e.method, site)) {
      all.push_back(e);
      total_seconds += e.seconds;
    }
  std::vector<const PoleEstimate*> valid;
  std::string declined;
  for (const PoleEstimate& e : all) {
    if (e.valid)
      valid.push_back(&e);
    else
      declined += (declined.empty() ? "" : "; ") + e.method + ": " + e.why_invalid;
  }
  PoleEstimate out;
  out.method = "auto";
  out.seconds = total_seconds;
  if (valid.empty()) {
    out.why_invalid = "no method could answer (" + declined + ")";
    return out;
  }
  // Two answers agree unless they are apart by more than the 99.9 % level of their combined
  // uncertainty (√χ²₂(0.999) = 3.72 σ against the 95 % cone's 2.45 σ: the root-sum-square of their
  // 95 % cones × 1.52); at the 95 % level one answer in ten of two calibrated methods would be
  // called a disagreement by chance. The centre is the answer with the most agreeing others
  // (ties: the narrowest cone); the rule is auto_choice (uncertainty.h).
  std::vector<AutoCandidate> candidates;
  for (const PoleEstimate* b : valid) {
    const Method* m = find_method(b->method);
    candidates.push_back({b->cone95_deg, b->sigma_deg, m && m->traits.auto_answers_alone});
  }
  const AutoChoice choice =
      auto_choice(candidates, [&](std::size_t a, std::size_t b) { return angle_deg(*valid[a], *valid[b]); });
  const PoleEstimate* centre = valid[choice.centre];
  std::vector<const PoleEstimate*> members, dissent;
  for (const std::size_t b : choice.members) members.push_back(valid[b]);
  for (const std::size_t b : choice.dissent) dissent.push_back(valid[b]);
  // A dissenting method that is as sure as the group and outvotes it cannot be told apart: the
  // data do not decide, so auto declines rather than pick.
  if (!choice.decided) {
    std::string who;
    for (const PoleEstimate* b : valid) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "%s %.1f° from %s (cones %.1f°, %.1f°)", b->method.c_str(),
                    angle_deg(*centre, *b), centre->method.c_str(), b->cone95_deg, centre->cone95_deg);
      if (b != centre) who += (who.empty() ? "" : "; ") + std::string(buf);
    }
    out.why_invalid = "the methods disagree beyond their 95 % cones: " + who;
    return out;
  }
  // The answer. That of a method whose answer stands alone when it agrees (auto_answers_alone,
  // method_registry.h: sun_vector_ephemeris), as it stands (its pole and its σ). Without it (a
  // capture without its site, or the ephemeris declined or outvoted), the inverse-variance mean of
  // the agreeing answers, stated with the σ of the sharpest of them: the methods read the same
  // frames, so their errors are correlated, and the mean's own σ would claim more than the data
  // hold (docs/calibration-history.md, "auto's rule", compares it with the alternatives).
  const PoleEstimate* sharpest = valid[choice.sharpest];
  const PoleEstimate* chosen = valid[choice.chosen];
  out = *chosen;
  std::string how = "the answer of " + chosen->method;
  if (choice.mean) {
    std::vector<Eigen::Vector2d> offsets;
    std::vector<double> sigmas;
    for (const PoleEstimate* b : members) {
      offsets.push_back(tangent_offset(*sharpest, *b));
      sigmas.push_back(b->sigma_deg);
    }
    const SkyImages frame = sky_geometry(stack, input);
    const Eigen::Vector3d end_level = tangent_moved(*sharpest, inverse_variance_mean(offsets, sigmas));
    const Eigen::Vector3d ncp_level = sharpest->is_north ? end_level : Eigen::Vector3d(-end_level);
    // The sharpest's answer moved to the mean: its σ stays, its position is the mean's (out.note is
    // written below from `how`; place_pole fills it only when the bearing is undefined).
    place_pole(out, frame, frame.level_from_camera.transpose() * ncp_level, input);
    how = "the inverse-variance mean of the agreeing answers, with the σ of the sharpest, " + sharpest->method;
    if (!out.heading_deg) how += " (" + out.note + ")";  // the mean's pole is near the zenith
  }
  out.method = "auto";
  out.seconds = total_seconds;
  std::string used, others;
  for (const PoleEstimate* b : members)
    if (b != chosen) used += ", " + b->method;
  for (const PoleEstimate* b : dissent) others += (others.empty() ? "" : ", ") + b->method;
  const std::string note = how + (used.empty() ? "" : " (agreeing: " + used.substr(2) + ")") +
                           (others.empty() ? "" : "; outvoted: " + others) +
                           (declined.empty() ? "" : "; declined: " + declined);
  out.note = chosen->note.empty() ? note : note + "; " + chosen->note;
  apply_uncertainty_bound(out, input.max_uncertainty_deg);
  return out;
}

namespace {

// What the methods of one stack share, made once: its prepared sky, mask judgments and E-vectors
// (stack_sky.h, read by every method and its jackknives' sub-runs), and the measures of the sky the
// calibration reads (the Rayleigh-law misfit, the unreadable shares), which auto's methods would
// each measure again.
struct SharedWork {
  SharedWork(const stack::Stack& stack, const InputOptions& input) : whole(stack, input) {}
  StackSky whole;
  std::optional<double> misfit;         // rayleigh_law_misfit of the whole stack
  std::optional<UnreadableSky> unread;  // unreadable_sky of its sky
};

// run_method of one method on `work`'s stack.
PoleEstimate run_with(SharedWork& work, const Method& method, ClassicImages* classic_images);

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

namespace {

// The calibration's gates (Method::calibration, method_registry.h): decline, with the numbers, where the study
// found the method's error unpredictable. `unread` receives the sky's unpolarized and clipped
// shares when a gate measured them, so that run_method's σ terms do not prepare the same images again.
void apply_gates(PoleEstimate& e, const MethodCalibration& c, const StackSky& whole,
                 std::optional<UnreadableSky>& unread) {
  const stack::Stack& stack = whole.stack();
  const InputOptions& input = whole.input();
  if (!e.valid || !input.calibrated) return;
  char buf[640];
  // The readings each gate compares (uncertainty.h gate_declines), filled as the gates need them.
  CalibrationReadings r;
  r.residual_deg = e.residual_deg;
  r.model_misfit = e.model_misfit;
  if (gate_declines(Gate::residual, c, r)) {
    std::snprintf(buf, sizeof buf,
                  "the fit's residual %.2f° is above %.2f°, beyond which this method's error was not predictable "
                  "in the calibration study (cloud, a sky unlike the method's model, or noise)",
                  e.residual_deg, c.max_residual_deg);
    e.valid = false;
    e.why_invalid = buf;
    return;
  }
  if (gate_declines(Gate::model_misfit, c, r)) {
    std::snprintf(buf, sizeof buf,
                  "the sky is not the model this method fits: its DoLP departs from the fitted law by %.1f %% of "
                  "the fitted maximum beyond the images' noise (a multiply scattering sky, haze or cloud), above "
                  "the %.1f %% beyond which this method's error was not predictable in the calibration study",
                  100.0 * e.model_misfit, 100.0 * c.max_model_misfit);
    e.valid = false;
    e.why_invalid = buf;
    return;
  }
  const double window_min =
      (stack.frames.back().truth.time.unix_seconds - stack.frames.front().truth.time.unix_seconds) / 60.0;
  r.window_min = window_min;
  if (gate_declines(Gate::window, c, r)) {
    std::snprintf(buf, sizeof buf,
                  "the window (%.0f min) is shorter than the %.0f min this method needs: the sun's arc is too "
                  "short to fix the pole reliably (calibration study)",
                  window_min, c.min_window_min);
    e.valid = false;
    e.why_invalid = buf;
    return;
  }
  // The sky images the sky-shape gates read, and the shares of it that no method reads, each
  // measured once and only if a gate needs it.
  const auto sky_images = [&]() -> const SkyImages& { return whole.sky(1, e.method); };
  const auto unreadable = [&]() -> const UnreadableSky& {
    if (!unread) unread = unreadable_sky(sky_images());
    return *unread;
  };
  if (input.cloud_gate && gate_set(Gate::unpolarized, c)) {
    const double share = r.unpolarized_share = unreadable().unpolarized;
    if (gate_declines(Gate::unpolarized, c, r)) {
      // Where the sensor clipped part of that sky, the reason says how much, and the cure.
      const double clipped = unreadable().clipped;
      const bool clipping = clipped > 0.005;
      char reading[256];
      if (clipping)
        std::snprintf(reading, sizeof reading,
                      "unpolarized or clipped (clipped by the sensor in some frame, which no method reads: %.0f %%; "
                      "a shorter exposure or a lower gain reads it)",
                      100.0 * clipped);
      else
        std::snprintf(reading, sizeof reading, "%s",
                      "unpolarized (DoLP below 20 % of its 99th percentile; cloud, or the neutral points of a "
                      "multiply scattering sky reaching beyond 40° of the sun and antisun)");
      std::snprintf(buf, sizeof buf,
                    "%s: %.0f %% of the sky away from the sun and antisun is %s, above the %.0f %% beyond which this "
                    "method's error was not predictable in the calibration study",
                    clipping ? "cloud, neutral points or clipping" : "cloud or neutral points", 100.0 * share, reading,
                    100.0 * c.max_unpolarized_share);
      e.valid = false;
      e.why_invalid = buf;
      return;
    }
  }
  if (gate_set(Gate::clipped, c)) {
    const double clipped = r.clipped_share = unreadable().clipped;
    if (gate_declines(Gate::clipped, c, r)) {
      std::snprintf(buf, sizeof buf,
                    "the sensor clipped the sky: %.0f %% of the sky away from the sun and antisun clipped in some "
                    "frame, which no method reads, above the %.0f %% beyond which this method's calibration holds "
                    "no answer; a shorter exposure or a lower gain reads it",
                    100.0 * clipped, 100.0 * c.max_clipped_share);
      e.valid = false;
      e.why_invalid = buf;
      return;
    }
  }
  if (gate_set(Gate::ring_anisotropy, c)) {
    const double a = r.ring_anisotropy = ring_anisotropy(sky_images());
    if (gate_declines(Gate::ring_anisotropy, c, r)) {
      std::snprintf(buf, sizeof buf,
                    "the sky is not the single-scattering shape this method assumes: around the sun its DoLP "
                    "varies by %.0f %% of its range at equal angle from it (neutral points moved by multiple "
                    "scattering), above the %.0f %% beyond which this method's error was not predictable in the "
                    "calibration study",
                    100.0 * a, 100.0 * c.max_ring_anisotropy);
      e.valid = false;
      e.why_invalid = buf;
    }
  }
}

}  // namespace

void apply_calibration_gates(PoleEstimate& e, const MethodCalibration& c, const stack::Stack& stack,
                             const InputOptions& input) {
  std::optional<UnreadableSky> unread;
  const StackSky whole(stack, input);
  apply_gates(e, c, whole, unread);
}

namespace {

PoleEstimate run_with(SharedWork& work, const Method& method, ClassicImages* classic_images) {
  const StackSky& whole = work.whole;
  const stack::Stack& stack = whole.stack();
  const InputOptions& input = whole.input();
  const MethodTraits& traits = method.traits;
  const auto t0 = std::chrono::steady_clock::now();
  check_site(method, stack, input);
  // The method's answer, with what its jackknives refit from its own work (method_registry.h
  // MethodRun); the refits it does not give rerun its bare run on a view of the stack.
  MethodRun run;
  if (method.run)
    run = method.run(whole, classic_images);
  else
    run.estimate = method.bare(SkyView(whole));
  PoleEstimate e = std::move(run.estimate);
  if (!e.valid) return e;
  // A sky far from Rayleigh's law bends what the methods that read its shape find, alike in every
  // frame and sector (method_registry.h misfit_measured; each entry says why): measured once per
  // stack for their gates and σ terms.
  if (traits.misfit_measured) {
    if (!work.misfit) work.misfit = rayleigh_law_misfit(SkyView(whole));
    e.model_misfit = *work.misfit;
  }
  const MethodCalibration& cal = method.calibration;
  std::optional<UnreadableSky>& unread = work.unread;  // the sky's unpolarized and clipped shares, once measured
  apply_gates(e, cal, whole, unread);
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

}  // namespace

PoleEstimate run_method(const stack::Stack& stack, std::string_view method,
                        const InputOptions& input, ClassicImages* classic_images) {
  if (method == "auto") return run_auto(stack, input);
  const Method& m = method_entry(method);
  SharedWork work(stack, input);
  return run_with(work, m, classic_images);
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

Stats summarize_values(std::vector<double> v) {
  Stats s;
  s.n = static_cast<int>(v.size());
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / static_cast<double>(v.size());
  const std::size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  const auto rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(n)));
  s.p95 = v[std::clamp<std::size_t>(rank, 1, n) - 1];
  s.max = v.back();
  return s;
}

std::vector<MethodSummary> summarize(const std::vector<EvaluationRow>& rows) {
  std::vector<std::string> order;
  for (const auto& r : rows)
    if (std::find(order.begin(), order.end(), r.estimate.method) == order.end())
      order.push_back(r.estimate.method);
  std::vector<MethodSummary> out;
  for (const auto& m : order) {
    MethodSummary s;
    s.method = m;
    std::vector<double> b, l, a;
    double secs = 0;
    for (const auto& r : rows) {
      if (r.estimate.method != m) continue;
      ++s.rows;
      secs += r.estimate.seconds;
      if (!r.estimate.valid) continue;
      ++s.valid;
      const Score sc = score(r.estimate, r.truth);
      if (sc.bearing_error_deg) b.push_back(std::abs(*sc.bearing_error_deg));
      l.push_back(std::abs(sc.latitude_error_deg));
      a.push_back(sc.angular_error_deg);
    }
    s.bearing_abs_deg = summarize_values(b);
    s.latitude_abs_deg = summarize_values(l);
    s.angular_deg = summarize_values(a);
    s.mean_seconds = s.rows ? secs / s.rows : 0.0;
    out.push_back(s);
  }
  return out;
}

std::string rows_csv(const std::vector<EvaluationRow>& rows) {
  std::ostringstream os;
  os << "dataset,method,valid,why_invalid,heading_deg,latitude_deg,azimuth_rel_deg,altitude_deg,"
        "is_north,true_heading_deg,true_latitude_deg,bearing_error_deg,latitude_error_deg,"
        "angular_error_deg,residual_deg,sigma_bearing_deg,sigma_latitude_deg,cone95_deg,sigma_deg,"
        "seconds,note\n";
  for (const auto& r : rows) {
    const PoleEstimate& e = r.estimate;
    os << csv_field(r.dataset) << ',' << csv_field(e.method) << ',' << (e.valid ? 1 : 0) << ','
       << csv_field(e.why_invalid) << ',';
    std::optional<Score> sc;
    if (e.valid) sc = score(e, r.truth);
    if (e.valid)
      os << num(e.heading_deg) << ',' << num(e.latitude_deg) << ',' << num(e.azimuth_rel_deg) << ','
         << num(e.altitude_deg) << ',' << (e.is_north ? 1 : 0) << ',';
    else
      os << ",,,,,";
    os << num(r.truth.heading_deg) << ',' << num(r.truth.site.latitude_deg) << ',';
    if (sc)
      os << num(sc->bearing_error_deg) << ',' << num(sc->latitude_error_deg) << ','
         << num(sc->angular_error_deg) << ',' << num(e.residual_deg) << ','
         << num(e.sigma_bearing_deg) << ',' << num(e.sigma_latitude_deg) << ',' << num(e.cone95_deg)
         << ',' << num(e.sigma_deg) << ',';
    else
      os << ",,,,,,,,";
    os << num(e.seconds) << ',' << csv_field(e.note) << '\n';
  }
  return os.str();
}

std::string summary_csv(const std::vector<MethodSummary>& summaries) {
  std::ostringstream os;
  os << "method,rows,valid";
  for (const char* q : {"bearing", "latitude", "angular"})
    for (const char* f : {"n", "mean", "median", "p95", "max"}) os << ',' << q << '_' << f;
  os << ",mean_seconds\n";
  for (const auto& s : summaries) {
    os << csv_field(s.method) << ',' << s.rows << ',' << s.valid;
    for (const Stats* st : {&s.bearing_abs_deg, &s.latitude_abs_deg, &s.angular_deg})
      os << ',' << st->n << ',' << num(st->mean) << ',' << num(st->median) << ',' << num(st->p95)
         << ',' << num(st->max);
    os << ',' << num(s.mean_seconds) << '\n';
  }
  return os.str();
}

std::string summary_text(const std::vector<MethodSummary>& summaries) {
  std::ostringstream os;
  os << std::left << std::setw(22) << "method" << std::right << std::setw(7) << "valid"
     << std::setw(12) << "|bearing|" << std::setw(10) << "p95" << std::setw(12) << "|lat|"
     << std::setw(10) << "p95" << std::setw(12) << "angular" << std::setw(10) << "p95"
     << std::setw(10) << "s/run" << '\n';
  os << std::left << std::setw(22) << "" << std::right << std::setw(7) << ""
     << std::setw(12) << "median deg" << std::setw(10) << "deg" << std::setw(12) << "median deg"
     << std::setw(10) << "deg" << std::setw(12) << "median deg" << std::setw(10) << "deg" << '\n';
  os << std::fixed;
  for (const auto& s : summaries) {
    const auto cell = [&](const Stats& st, double v, int w) {
      if (st.n == 0)
        os << std::setw(w) << "-";
      else
        os << std::setw(w) << std::setprecision(3) << v;
    };
    os << std::left << std::setw(22) << s.method << std::right << std::setw(7)
       << (std::to_string(s.valid) + "/" + std::to_string(s.rows));
    cell(s.bearing_abs_deg, s.bearing_abs_deg.median, 12);
    cell(s.bearing_abs_deg, s.bearing_abs_deg.p95, 10);
    cell(s.latitude_abs_deg, s.latitude_abs_deg.median, 12);
    cell(s.latitude_abs_deg, s.latitude_abs_deg.p95, 10);
    cell(s.angular_deg, s.angular_deg.median, 12);
    cell(s.angular_deg, s.angular_deg.p95, 10);
    os << std::setw(10) << std::setprecision(3) << s.mean_seconds << '\n';
  }
  return os.str();
}

}  // namespace skypol::skypole
