// The jackknife and the covariance → σ, cone conversion (uncertainty.h).
#include "skypole/uncertainty.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "sky/units.h"

namespace skypol::skypole {
namespace {

constexpr double kChi2_2_95 = 5.991464547107979;  // χ²₂ quantile at 0.95

// Unit azimuth and altitude axes of the tangent plane at the level-frame direction p.
void tangent_axes(const Eigen::Vector3d& p, Eigen::Vector3d& e_az, Eigen::Vector3d& e_alt) {
  const double horiz = std::hypot(p.x(), p.y());
  const double az = horiz > 1e-12 ? std::atan2(p.x(), p.y()) : 0.0;
  const double el = std::atan2(p.z(), horiz);
  e_az = Eigen::Vector3d(std::cos(az), -std::sin(az), 0.0);
  e_alt = Eigen::Vector3d(-std::sin(el) * std::sin(az), -std::sin(el) * std::cos(az), std::cos(el));
}

// The larger eigenvalue of a 2×2 covariance, at least 0.
double lambda_max(const Eigen::Matrix2d& c) {
  return std::max(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(c).eigenvalues().maxCoeff(), 0.0);
}

std::string deg_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f°", v);
  return buf;
}

}  // namespace

void set_uncertainty(PoleEstimate& e, const Eigen::Matrix2d& c) {
  const double alt = e.altitude_deg * kRadPerDeg;
  e.sigma_latitude_deg = std::sqrt(std::max(c(1, 1), 0.0)) / kRadPerDeg;
  const double cos_alt = std::cos(alt);
  const double sb = cos_alt > 1e-9 ? std::sqrt(std::max(c(0, 0), 0.0)) / cos_alt / kRadPerDeg : 180.0;
  e.sigma_bearing_deg = std::min(sb, 180.0);
  e.sigma_deg = sigma_deg_of(c);
  e.cone95_deg = cone95_deg_of(c);
}

Eigen::Vector2d tangent_offset(const PoleEstimate& at, const PoleEstimate& other) {
  const Eigen::Vector3d p = at.pole_level.normalized();
  // `other`'s NCP, expressed as the end `at` reports.
  const Eigen::Vector3d other_ncp = other.is_north ? other.pole_level : Eigen::Vector3d(-other.pole_level);
  const Eigen::Vector3d q = (at.is_north ? other_ncp : Eigen::Vector3d(-other_ncp)).normalized();
  // Log map: the tangent vector towards q whose length is the angle between p and q.
  const Eigen::Vector3d perp = q - q.dot(p) * p;
  const double angle = std::atan2(perp.norm(), q.dot(p));
  if (perp.norm() < 1e-15) return Eigen::Vector2d::Zero();
  const Eigen::Vector3d v = perp.normalized() * angle;
  Eigen::Vector3d e_az, e_alt;
  tangent_axes(p, e_az, e_alt);
  return {v.dot(e_az), v.dot(e_alt)};
}

Eigen::Vector3d tangent_moved(const PoleEstimate& at, const Eigen::Vector2d& offset) {
  const Eigen::Vector3d p = at.pole_level.normalized();
  const double angle = offset.norm();
  if (angle < 1e-15) return p;
  Eigen::Vector3d e_az, e_alt;
  tangent_axes(p, e_az, e_alt);
  const Eigen::Vector3d towards = (offset.x() * e_az + offset.y() * e_alt) / angle;
  return (std::cos(angle) * p + std::sin(angle) * towards).normalized();
}

stack::Stack frames_kept(const stack::Stack& stack, const std::vector<std::uint8_t>& keep) {
  stack::Stack sub;
  sub.camera = stack.camera;
  sub.bands = stack.bands;
  sub.camera_description = stack.camera_description;
  sub.scene_text = stack.scene_text;
  sub.truth_known = stack.truth_known;
  sub.site_known = stack.site_known;
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) sub.frames.push_back(stack.frames[i]);
  return sub;
}

int sector_of(double x, double y, const Eigen::Vector2d& c, int sectors) {
  const double t = (std::atan2(y - c.y(), x - c.x()) + std::numbers::pi) / (2 * std::numbers::pi);
  return std::clamp(static_cast<int>(t * sectors), 0, sectors - 1);
}

std::vector<std::uint8_t> sector_map(int width, int height, const Eigen::Vector2d& c, int sectors) {
  if (sectors < 1 || sectors > 255)
    throw std::invalid_argument("sky sectors: 1 to 255, got " + std::to_string(sectors));
  std::vector<std::uint8_t> map(static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0)));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      map[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] =
          static_cast<std::uint8_t>(sector_of(x, y, c, sectors));
  return map;
}

stack::Stack sector_left_out(const stack::Stack& stack, const Eigen::Vector2d& c, int g, int sectors) {
  stack::Stack sub = stack;
  // The sectors' map, made once for the frames' size (every frame of a stack has the same).
  std::vector<std::uint8_t> map;
  int w = -1, h = -1;
  for (stack::Frame& f : sub.frames) {
    if (f.width != w || f.height != h) {
      w = f.width, h = f.height;
      map = sector_map(w, h, c, sectors);
    }
    std::vector<float>& mask = f.channels["mask"];
    if (mask.size() != map.size()) mask.assign(map.size(), 1.0f);  // a stack without a mask: every pixel was usable
    for (std::size_t i = 0; i < map.size(); ++i)
      if (map[i] == g) mask[i] = 0.0f;
  }
  return sub;
}

std::optional<Eigen::Matrix2d> group_jackknife(PoleEstimate& e, int k, const std::function<PoleEstimate(int)>& sub,
                                               const std::string& what, const std::string& cause) {
  if (!e.valid) return std::nullopt;
  // The sub-runs are independent: they run in parallel, and their answers are read in order as a
  // sequential run would read them (the first group that fails is the one reported, an exception
  // other than invalid_argument is thrown only when its group is reached), so that the result does
  // not depend on the threads.
  std::vector<PoleEstimate> subs(static_cast<std::size_t>(std::max(k, 0)));
  std::vector<std::exception_ptr> errors(subs.size());
  tbb::parallel_for(0, k, [&](int g) {
    try {
      subs[static_cast<std::size_t>(g)] = sub(g);
    } catch (...) {
      errors[static_cast<std::size_t>(g)] = std::current_exception();
    }
  });
  std::vector<Eigen::Vector2d> offsets;
  for (int g = 0; g < k; ++g) {
    PoleEstimate& s = subs[static_cast<std::size_t>(g)];
    try {
      if (errors[static_cast<std::size_t>(g)]) std::rethrow_exception(errors[static_cast<std::size_t>(g)]);
    } catch (const std::invalid_argument& err) {
      s.valid = false;
      s.why_invalid = err.what();
    }
    const std::string without = "unstable: without " + what + " " + std::to_string(g + 1) + " of " + std::to_string(k);
    if (!s.valid) {
      e.valid = false;
      e.why_invalid = without + " the method finds no pole (" + s.why_invalid + "); " + cause;
      return std::nullopt;
    }
    if (s.is_north != e.is_north && std::abs(e.latitude_deg) > 1.0) {
      e.valid = false;
      e.why_invalid = without + " the method finds the other celestial pole (north/south undecidable; " + cause + ")";
      return std::nullopt;
    }
    offsets.push_back(tangent_offset(e, s));
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& d : offsets) mean += d;
  mean /= static_cast<double>(offsets.size());
  Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
  for (const auto& d : offsets) c += (d - mean) * (d - mean).transpose();
  c *= static_cast<double>(k - 1) / static_cast<double>(k);
  // The jackknife mean's distance from the full answer is a bias the scatter does not show;
  // count it (its square) in both axes' variance.
  c += (mean * mean.transpose()) * static_cast<double>(k - 1);
  return c;
}

std::optional<Eigen::Matrix2d> frame_jackknife(PoleEstimate& e, int n,
                                               const std::function<PoleEstimate(const std::vector<std::uint8_t>&)>& refit,
                                               int max_groups) {
  if (!e.valid) return std::nullopt;
  if (n < 3) {
    e.valid = false;
    e.why_invalid = "too few frames to measure the uncertainty (" + std::to_string(n) +
                    "; the jackknife needs 3)";
    return std::nullopt;
  }
  const int k = frame_jackknife_groups(n, max_groups);
  return group_jackknife(
      e, k,
      [&](int g) {
        std::vector<std::uint8_t> keep(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) keep[static_cast<std::size_t>(i)] = i % k != g ? 1 : 0;
        return refit(keep);
      },
      "frame group", "the window is too short, too sparse or too noisy for a stated uncertainty");
}

// The sector jackknife from the method's answer without sector g of `sectors`: a run on a view of
// the stack with that sector left out (stack_sky.h SkyView::without_sector, the same as a run on
// sector_left_out), or great_circle's refit of its cached zero crossings outside it (great_circle.h).
std::optional<Eigen::Matrix2d> sector_jackknife(PoleEstimate& e, int sectors,
                                                const std::function<PoleEstimate(int g)>& without_sector) {
  return group_jackknife(e, sectors, without_sector, "sky sector",
                         "the answer rests on one part of the sky (cloud, a neutral point, saturation)");
}

double sigma_deg_of(const Eigen::Matrix2d& c) { return std::sqrt(lambda_max(c)) / kRadPerDeg; }

double cone95_deg_of(const Eigen::Matrix2d& c) { return std::min(std::sqrt(kChi2_2_95 * lambda_max(c)) / kRadPerDeg, 180.0); }

int frame_jackknife_groups(int frames, int max_groups) { return std::min(frames, std::max(max_groups, 2)); }

double few_groups_widening2(double frames_var, int frame_groups, double sectors_var, int sector_groups) {
  // Welch–Satterthwaite: ν = (A + B)² / (A²/ν_A + B²/ν_B), A = frames_var, B = sectors_var.
  double den = 0;
  if (frame_groups > 1) den += frames_var * frames_var / (frame_groups - 1);
  if (sector_groups > 1) den += sectors_var * sectors_var / (sector_groups - 1);
  const double sum = (frame_groups > 1 ? frames_var : 0.0) + (sector_groups > 1 ? sectors_var : 0.0);
  if (!(sum > 0) || !(den > 0)) return 1.0;
  const double nu = std::max(sum * sum / den, 1.0);
  // The 95 % point of F(2, ν): 1 − (1 + 2x/ν)^(−ν/2) = 0.95 ⟹ x = (ν/2)(0.05^(−2/ν) − 1); ν → ∞: −ln 0.05.
  const double ln05 = std::log(0.05);
  return (nu / 2.0) * std::expm1(-2.0 / nu * ln05) / -ln05;
}

Eigen::Matrix2d stated_covariance(const Jackknives& j, double a, double b, double floor_deg, bool widen) {
  const double floor = floor_deg * kRadPerDeg;
  const Eigen::Matrix2d jack = a * a * j.frames + b * b * j.sectors;
  const double w2 = widen ? few_groups_widening2(a * a * lambda_max(j.frames), j.frame_groups,
                                                 b * b * lambda_max(j.sectors), b > 0 ? j.sector_groups : 0)
                          : 1.0;
  return w2 * jack + Eigen::Matrix2d::Identity() * floor * floor;
}

Eigen::Matrix2d calibrated_covariance(const MethodCalibration& c, const Jackknives& j, const CalibrationReadings& r) {
  return stated_covariance(j, c.inflation, calibrated_sector_factor(c, r), calibrated_floor_deg(c, r));
}

Eigen::Matrix2d uncalibrated_covariance(const Jackknives& j) {
  return stated_covariance(j, 1.0, 1.0, kUncalibratedFloorDeg, false);
}

void set_stated_uncertainty(PoleEstimate& e, const Jackknives& j, const Eigen::Matrix2d& covariance_rad2) {
  e.jackknife_frames_rad2 = j.frames;
  e.jackknife_sectors_rad2 = j.sectors;
  e.jackknife_frame_groups = j.frame_groups;
  set_uncertainty(e, covariance_rad2);
}

const std::vector<std::pair<const char*, double MethodCalibration::*>>& calibration_fields() {
  using C = MethodCalibration;
  static const std::vector<std::pair<const char*, double C::*>> fields = {
      {"inflation", &C::inflation},
      {"floor_deg", &C::floor_deg},
      {"residual_share", &C::residual_share},
      {"max_residual_deg", &C::max_residual_deg},
      {"min_window_min", &C::min_window_min},
      {"max_unpolarized_share", &C::max_unpolarized_share},
      {"residual_pixels", &C::residual_pixels},
      {"max_ring_anisotropy", &C::max_ring_anisotropy},
      {"max_model_misfit", &C::max_model_misfit},
      {"max_clipped_share", &C::max_clipped_share},
      {"sector_inflation", &C::sector_inflation},
      {"unpolarized_deg", &C::unpolarized_deg},
      {"sector_unpolarized", &C::sector_unpolarized},
      {"sector_clipped", &C::sector_clipped},
      {"elevation_share", &C::elevation_share},
      {"misfit_deg", &C::misfit_deg},
  };
  return fields;
}

double calibrated_floor_deg(const MethodCalibration& c, const CalibrationReadings& r) {
  // The residual term counts only the part of the residual beyond what the pixel grid itself
  // imposes (classic's blob is a few pixels wide at any resolution: that much says nothing of its
  // error, and at binning 16 a pixel is 1.5°). std::max(0, NaN) is 0: no residual, no term.
  const double residual_excess = std::max(0.0, r.residual_deg - c.residual_pixels * r.pixel_deg);
  const double terms[] = {c.floor_deg, c.residual_share * residual_excess, c.unpolarized_deg * r.unpolarized_share,
                          c.elevation_share * r.sun_elevation_misfit_deg, c.misfit_deg * r.model_misfit};
  double sum = 0;
  for (const double t : terms) sum += t * t;
  return std::sqrt(sum);
}

double calibrated_sector_factor(const MethodCalibration& c, const CalibrationReadings& r) {
  return c.sector_inflation + c.sector_unpolarized * r.unpolarized_share + c.sector_clipped * r.clipped_share;
}

bool reads_unreadable_sky(const MethodCalibration& c) {
  return c.unpolarized_deg > 0 || c.sector_unpolarized > 0 || c.sector_clipped > 0;
}

const char* gate_field(Gate g) {
  switch (g) {
    case Gate::residual: return "max_residual_deg";
    case Gate::model_misfit: return "max_model_misfit";
    case Gate::window: return "min_window_min";
    case Gate::unpolarized: return "max_unpolarized_share";
    case Gate::clipped: return "max_clipped_share";
    case Gate::ring_anisotropy: return "max_ring_anisotropy";
    case Gate::none: break;
  }
  return "";
}

bool gate_set(Gate g, const MethodCalibration& c) {
  switch (g) {
    case Gate::residual: return std::isfinite(c.max_residual_deg);
    case Gate::model_misfit: return std::isfinite(c.max_model_misfit);
    case Gate::window: return c.min_window_min > 0;
    case Gate::unpolarized: return std::isfinite(c.max_unpolarized_share);
    case Gate::clipped: return std::isfinite(c.max_clipped_share);
    case Gate::ring_anisotropy: return std::isfinite(c.max_ring_anisotropy);
    case Gate::none: break;
  }
  return false;
}

bool gate_declines(Gate g, const MethodCalibration& c, const CalibrationReadings& r) {
  switch (g) {
    case Gate::residual: return r.residual_deg > c.max_residual_deg;
    case Gate::model_misfit: return r.model_misfit > c.max_model_misfit;
    case Gate::window: return r.window_min < c.min_window_min;
    case Gate::unpolarized: return r.unpolarized_share > c.max_unpolarized_share;
    case Gate::clipped: return r.clipped_share > c.max_clipped_share;
    case Gate::ring_anisotropy: return r.ring_anisotropy > c.max_ring_anisotropy;
    case Gate::none: break;
  }
  return false;
}

Gate first_declining_gate(const MethodCalibration& c, const CalibrationReadings& r, bool cloud_gate) {
  for (const Gate g : {Gate::residual, Gate::model_misfit, Gate::window, Gate::unpolarized, Gate::clipped,
                       Gate::ring_anisotropy}) {
    if (g == Gate::unpolarized && !cloud_gate) continue;
    if (gate_declines(g, c, r)) return g;
  }
  return Gate::none;
}

bool within_uncertainty_bound(double cone95_deg, double max_cone95_deg) {
  return !std::isfinite(max_cone95_deg) || !(cone95_deg > max_cone95_deg);
}

std::pair<double, double> wilson_interval95(double hits, double n) {
  if (!(n > 0)) return {std::nan(""), std::nan("")};
  constexpr double z = 1.959963984540054;  // the normal distribution's 97.5 % quantile
  const double p = hits / n, z2n = z * z / n;
  const double centre = (p + 0.5 * z2n) / (1.0 + z2n);
  const double half = z / (1.0 + z2n) * std::sqrt(p * (1.0 - p) / n + 0.25 * z2n / n);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

bool answers_agree(double angle_deg, double cone95_a_deg, double cone95_b_deg) {
  return angle_deg <= kAutoAgreeScale * std::hypot(cone95_a_deg, cone95_b_deg);
}

AutoChoice auto_choice(std::span<const AutoCandidate> answers,
                       const std::function<double(std::size_t, std::size_t)>& angle_deg) {
  AutoChoice out;
  const std::size_t n = answers.size();
  if (n == 0) return out;
  const auto agree = [&](std::size_t a, std::size_t b) {
    return a == b || answers_agree(angle_deg(a, b), answers[a].cone95_deg, answers[b].cone95_deg);
  };
  std::size_t best = 0;
  for (std::size_t a = 0; a < n; ++a) {
    std::size_t count = 0;
    for (std::size_t b = 0; b < n; ++b) count += agree(a, b) ? 1 : 0;
    if (a == 0 || count > best || (count == best && answers[a].cone95_deg < answers[out.centre].cone95_deg)) {
      out.centre = a;
      best = count;
    }
  }
  for (std::size_t b = 0; b < n; ++b) (agree(out.centre, b) ? out.members : out.dissent).push_back(b);
  // A dissenting method that is as sure as the group and outvotes it cannot be told apart: the
  // data do not decide.
  out.decided = out.members.size() > out.dissent.size() || n == 1;
  out.sharpest = out.members.front();
  for (const std::size_t b : out.members) {
    if (answers[b].sigma_deg < answers[out.sharpest].sigma_deg) out.sharpest = b;
    if (!out.alone && answers[b].answers_alone) out.alone = b;
  }
  out.chosen = out.alone ? *out.alone : out.sharpest;
  out.mean = !out.alone && out.members.size() > 1;
  return out;
}

Eigen::Vector2d inverse_variance_mean(std::span<const Eigen::Vector2d> offsets, std::span<const double> sigmas) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double weights = 0;
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    const double w = 1.0 / std::max(sigmas[i] * sigmas[i], 1e-12);
    sum += w * offsets[i];
    weights += w;
  }
  return sum / weights;
}

double pixel_angle_deg(const camera::Camera& camera) {
  const camera::Intrinsics& k = camera.lens().intrinsics();
  const auto a = camera.lens().ray(Eigen::Vector2d(k.cx, k.cy));
  const auto b = camera.lens().ray(Eigen::Vector2d(k.cx + 1.0, k.cy));
  if (!a || !b) return 0.0;
  return deg_from_rad(std::acos(std::clamp(a->normalized().dot(b->normalized()), -1.0, 1.0)));
}

void apply_uncertainty_bound(PoleEstimate& e, double max_cone95_deg) {
  if (!e.valid) return;
  if (!within_uncertainty_bound(e.cone95_deg, max_cone95_deg)) {
    e.valid = false;
    e.why_invalid = "uncertainty above the bound: 95 % cone " + deg_text(e.cone95_deg) + " > " +
                    deg_text(max_cone95_deg) + " (σ bearing " + deg_text(e.sigma_bearing_deg) +
                    ", σ latitude " + deg_text(e.sigma_latitude_deg) + ")";
  }
}

}  // namespace skypol::skypole
