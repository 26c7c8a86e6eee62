// Minimum of DoLP's variance over time on the sphere (method in invariance.h).
#include "skypole/invariance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "sky/sun.h"
#include "sky/units.h"
#include "skypole/enum_names.h"
#include "skypole/sky_mask.h"
#include "skypole/stack_sky.h"
#include "skypole/invariance_refine.h"

namespace skypol::skypole {
namespace {

// The other sense of rotation must fit at least this much worse for the co-rotating fit to say
// which pole it found.
constexpr double kMinSenseContrast = 2.0;

struct Cost {
  const SkyImages& sky;
  const std::vector<std::vector<float>>& images;
  Eigen::MatrixXd h;  // N×N residual projector

  // V(d), or nullopt where d does not image onto valid pixels.
  std::optional<double> operator()(const Eigen::Vector3d& d) const {
    const auto px = sky.lens->project(d);
    if (!px) return std::nullopt;
    Eigen::VectorXd v(static_cast<Eigen::Index>(images.size()));
    for (std::size_t t = 0; t < images.size(); ++t) {
      const auto s = sample_bilinear(images[t], sky, *px);
      if (!s) return std::nullopt;
      v(static_cast<Eigen::Index>(t)) = *s;
    }
    return (h * v).squaredNorm() / static_cast<double>(images.size());
  }
};

Eigen::MatrixXd residual_projector(const std::vector<double>& tau, bool linear) {
  const auto n = static_cast<Eigen::Index>(tau.size());
  Eigen::MatrixXd x(n, linear ? 2 : 1);
  for (Eigen::Index t = 0; t < n; ++t) {
    x(t, 0) = 1;
    if (linear) x(t, 1) = tau[static_cast<std::size_t>(t)];
  }
  const Eigen::MatrixXd xtx = x.transpose() * x;
  return Eigen::MatrixXd::Identity(n, n) - x * xtx.ldlt().solve(x.transpose());
}

// The sun's motion since the middle instant, from the frames' times (ERFA; the changes of hour
// angle and declination do not depend on the site), and the suns the images show.
SunMotion sun_motion(const FrameRefs& frames, const std::vector<std::optional<Eigen::Vector3d>>& suns,
                     bool drift) {
  SunMotion m;
  const sky::Instant mid{0.5 * (frames.front()->truth.time.unix_seconds +
                                frames.back()->truth.time.unix_seconds)};
  const sky::Sun at_mid = sky::sun_position(sky::Site{}, mid);
  for (const stack::Frame* frame : frames) {
    const sky::Sun s = sky::sun_position(sky::Site{}, frame->truth.time);
    m.hour_angle_change.push_back(std::remainder(s.hour_angle - at_mid.hour_angle, 2 * kPi));
    m.declination_change.push_back(s.declination - at_mid.declination);
  }
  if (!drift) m.declination_change.clear();
  for (std::size_t t = 0; t < suns.size(); ++t)
    if (suns[t]) m.suns_in_frames.emplace_back(t, *suns[t]);
  return m;
}

}  // namespace

constexpr EnumNames<Detrend, 3> kDetrendNames{
    {{Detrend::none, "none"}, {Detrend::linear, "linear"}, {Detrend::automatic, "automatic"}}};
constexpr EnumNames<Refine, 3> kRefineNames{
    {{Refine::per_frame, "per_frame"}, {Refine::corotating, "corotating"}, {Refine::automatic, "automatic"}}};

Detrend parse_detrend(std::string_view name) { return enum_from_name(kDetrendNames, name, "detrend"); }
std::string_view detrend_name(Detrend d) { return enum_name(kDetrendNames, d); }
Refine parse_refine(std::string_view name) { return enum_from_name(kRefineNames, name, "refine"); }
std::string_view refine_name(Refine r) { return enum_name(kRefineNames, r); }

HemisphereDecision reconcile_hemisphere(HemisphereDecision suns, int pattern_sense, double pattern_contrast,
                                        double min_contrast, Hemisphere hint) {
  const bool pattern_speaks = pattern_sense != 0 && pattern_contrast >= min_contrast;
  const bool pattern_north = pattern_sense < 0;
  if (!pattern_speaks) return suns;
  if (!suns.ok) {
    // The suns alone could not tell (too few in view, or too little motion between them): the
    // co-rotating fit saw the whole pattern turn, clockwise about the NCP.
    HemisphereDecision d;
    d.ok = true;
    d.is_north = pattern_north;
    d.source = "the sense the sky's pattern turns in (co-rotating fit)";
    return d;
  }
  if (!suns.from_suns || pattern_north == suns.is_north) return suns;
  if (hint != Hemisphere::automatic) {
    // The suns overrode the hint, and the whole pattern sides with it: two against one.
    HemisphereDecision d;
    d.ok = true;
    d.is_north = pattern_north;
    d.source = std::string("hint: hemisphere = ") + (pattern_north ? "north" : "south") +
               " was given and the sky's pattern turns as it says (co-rotating fit), though the suns found "
               "in the frames (lowest DoLP) turn the other way; a neutral point may have been taken for the sun";
    return d;
  }
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "cannot tell north from south: the suns found in the frames (lowest DoLP) turn about the "
                "axis as about the %s, the sky's pattern as about the %s (it fits %.1f× better than the "
                "other sense); a neutral point may have been taken for the sun; pass hemisphere = north or south",
                suns.is_north ? "NCP" : "SCP", suns.is_north ? "SCP" : "NCP", pattern_contrast);
  HemisphereDecision d;
  d.why = buf;
  return d;
}

InvarianceResult estimate_invariance(const stack::Stack& stack, const InvarianceParams& params) {
  const StackSky whole(stack, params.input);
  return estimate_invariance(SkyView(whole), params);
}

InvarianceResult estimate_invariance(const SkyView& view, const InvarianceParams& params) {
  const auto t_start = std::chrono::steady_clock::now();
  const char* method = "invariance";
  if (!(params.coarse_step_deg > 0.05 && params.coarse_step_deg <= 20))
    throw std::invalid_argument("invariance: coarse_step_deg must be in (0.05, 20], got " +
                                std::to_string(params.coarse_step_deg));
  if (params.per_frame_degree < 2 || params.per_frame_degree > 6 || params.corotating_degree < 2 ||
      params.corotating_degree > 8)
    throw std::invalid_argument("invariance: per_frame_degree must be in [2, 6] and corotating_degree in [2, 8]");
  if (!(params.corotating_min_radius_deg > 0 && params.corotating_min_radius_deg <= params.corotating_radius_deg &&
        params.corotating_radius_deg < 60))
    throw std::invalid_argument("invariance: need 0 < corotating_min_radius_deg <= corotating_radius_deg < 60");
  SkyImages sky = view.prepared(3, method);
  if (params.input.sky_mask) apply_mask(sky, view.sky_mask(sky));
  const double radius =
      params.filter_radius_px.value_or(default_filter_radius_px(sky.width, sky.height));
  const double fit_radius = params.fit_radius_px.value_or(
      std::max(3.0, 0.01 * std::min(sky.width, sky.height)));
  const std::vector<std::vector<float>> filtered = view.filtered(sky, radius);

  InvarianceResult result;
  const double span_h = (sky.times_s.back() - sky.times_s.front()) / 3600.0;
  result.detrended = params.detrend == Detrend::linear ||
                     (params.detrend == Detrend::automatic && sky.times_known &&
                      span_h >= params.auto_detrend_min_hours && sky.frames() >= 5);
  std::vector<double> tau;
  for (std::size_t t = 0; t < sky.frames(); ++t)
    tau.push_back(sky.times_known ? sky.times_s[t] / std::max(1.0, sky.times_s.back())
                                  : static_cast<double>(t));
  const Cost cost{sky, filtered, residual_projector(tau, result.detrended)};

  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  };
  const auto fail = [&](std::string why) {
    result.estimate = invalid_estimate(method, std::move(why));
    result.estimate.seconds = seconds();
    return result;
  };

  // Coarse: Fibonacci lattice of the sky (level frame) above min_elevation.
  const double step = params.coarse_step_deg * kRadPerDeg;
  const int m = static_cast<int>(std::ceil(4 * kPi / (step * step)));
  const double golden = kPi * (3 - std::sqrt(5.0));
  const double min_z = std::sin(params.input.min_elevation_deg * kRadPerDeg);
  const Eigen::Matrix3d camera_from_level = sky.level_from_camera.transpose();
  std::vector<std::pair<double, Eigen::Vector3d>> coarse;
  for (int k = 0; k < m; ++k) {
    const double z = 1 - 2 * (k + 0.5) / m;
    if (z < min_z) continue;
    const double rr = std::sqrt(std::max(0.0, 1 - z * z)), ph = k * golden;
    const Eigen::Vector3d d = camera_from_level * Eigen::Vector3d(rr * std::cos(ph), rr * std::sin(ph), z);
    if (const auto v = cost(d)) coarse.emplace_back(*v, d);
  }
  if (coarse.size() < 3) return fail("too little of the sky is visible for the coarse search");
  std::sort(coarse.begin(), coarse.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3d> starts;
  for (const auto& [v, d] : coarse) {
    bool far = true;
    for (const auto& s : starts) far = far && std::acos(std::clamp(s.dot(d), -1.0, 1.0)) > 4 * step;
    if (far) starts.push_back(d);
    if (static_cast<int>(starts.size()) >= std::max(1, params.candidates)) break;
  }

  // Fine: pattern search in the tangent plane.
  double best_v = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_d = starts.front();
  for (Eigen::Vector3d c : starts) {
    double s = step;
    double vc = cost(c).value_or(std::numeric_limits<double>::infinity());
    const double stop = 0.25 * pixel_angle(sky, c);
    for (int it = 0; it < 200 && s > stop; ++it) {
      Eigen::Vector3d e1, e2;
      tangent_basis(c, e1, e2);
      Eigen::Vector3d nb = c;
      double vb = vc;
      for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i) {
          if (i == 0 && j == 0) continue;
          const Eigen::Vector3d d = (c + s * (i * e1 + j * e2)).normalized();
          if ((sky.level_from_camera * d).z() < min_z) continue;
          const auto v = cost(d);
          if (v && *v < vb) {
            vb = *v;
            nb = d;
          }
        }
      if (vb < vc) {
        c = nb;
        vc = vb;
      } else {
        s *= 0.5;
      }
    }
    if (vc < best_v) {
      best_v = vc;
      best_d = c;
    }
  }

  const std::vector<std::optional<Eigen::Vector3d>> suns = find_suns(sky, filtered);
  result.corotating = params.refine == Refine::corotating ||
                      (params.refine == Refine::automatic && sky.times_known);
  if (result.corotating && !sky.times_known)
    throw std::invalid_argument("invariance: the co-rotating refinement needs frames taken at "
                                "different times");
  const SunMotion motion = result.corotating ? sun_motion(view.frames(), suns, params.model_declination_drift)
                                             : SunMotion{};
  const SubPixel sp =
      result.corotating
          ? corotating_refine(sky, motion, result.detrended, best_d,
                              params.corotating_radius_deg, params.corotating_min_radius_deg,
                              params.corotating_degree, params.sectors)
          : per_frame_refine(sky, cost.h, best_d, fit_radius, params.per_frame_degree);
  if (!sp.ok) return fail(sp.why);

  // Which end: the minimum is above the horizon; the sun's rotation says if it is the NCP.
  HemisphereDecision hemi = decide_hemisphere(suns, sp.d, params.input.hemisphere,
                                              sky.times_known ? sky.times_s : std::vector<double>{});
  hemi = reconcile_hemisphere(std::move(hemi), sp.sense, sp.sense_contrast, kMinSenseContrast,
                              params.input.hemisphere);
  if (!hemi.ok) return fail(hemi.why);
  result.estimate = make_estimate(method, sky, hemi.is_north ? sp.d : Eigen::Vector3d(-sp.d), params.input);
  result.estimate.note += (result.estimate.note.empty() ? "" : "; ") +
                          std::string("hemisphere from ") + hemi.source;
  char window[96];
  std::snprintf(window, sizeof window, "; sub-pixel: %s model over %.1f deg",
                result.corotating ? "co-rotating" : "per-frame", sp.window_rad / kRadPerDeg);
  result.estimate.note += window;
  if (result.corotating && params.model_declination_drift && motion.suns_in_frames.empty())
    result.estimate.note += "; the sun's declination drift is not modelled (no sun found in the images)";
  result.dolp_rms_at_pole = std::sqrt(sp.v);
  result.window_deg = sp.window_rad / kRadPerDeg;
  result.rotation_sense = sp.sense;
  result.rotation_sense_contrast = sp.sense_contrast;
  result.estimate.residual_deg = sp.sigma_rad / kRadPerDeg;
  for (const auto& d : sp.without_sector)
    result.without_sector.push_back(
        d ? make_estimate(method, sky, hemi.is_north ? *d : Eigen::Vector3d(-*d), params.input)
          : invalid_estimate(method, "without this sector of the window about the pole the fit finds no "
                                     "minimum of DoLP variance"));
  result.estimate.seconds = seconds();
  return result;
}

}  // namespace skypol::skypole
