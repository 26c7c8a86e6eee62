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

namespace skypol::skypole {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
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
  const double alt = e.altitude_deg * kDeg;
  e.sigma_latitude_deg = std::sqrt(std::max(c(1, 1), 0.0)) / kDeg;
  const double cos_alt = std::cos(alt);
  const double sb = cos_alt > 1e-9 ? std::sqrt(std::max(c(0, 0), 0.0)) / cos_alt / kDeg : 180.0;
  e.sigma_bearing_deg = std::min(sb, 180.0);
  const double lmax = lambda_max(c);
  e.sigma_deg = std::sqrt(lmax) / kDeg;
  e.cone95_deg = std::min(std::sqrt(kChi2_2_95 * lmax) / kDeg, 180.0);
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

double sigma_deg_of(const Eigen::Matrix2d& c) { return std::sqrt(lambda_max(c)) / kDeg; }

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

void set_calibrated_uncertainty(PoleEstimate& e, const Jackknives& j, double a, double b, double floor_deg,
                                bool widen) {
  const double floor = floor_deg * kDeg;
  const Eigen::Matrix2d jack = a * a * j.frames + b * b * j.sectors;
  const double w2 = widen ? few_groups_widening2(a * a * lambda_max(j.frames), j.frame_groups,
                                                 b * b * lambda_max(j.sectors),
                                                 b > 0 ? j.sector_groups : 0)
                          : 1.0;
  e.jackknife_frames_rad2 = j.frames;
  e.jackknife_sectors_rad2 = j.sectors;
  e.jackknife_frame_groups = j.frame_groups;
  set_uncertainty(e, w2 * jack + Eigen::Matrix2d::Identity() * floor * floor);
}

double pixel_angle_deg(const camera::Camera& camera) {
  const camera::Intrinsics& k = camera.lens().intrinsics();
  const auto a = camera.lens().ray(Eigen::Vector2d(k.cx, k.cy));
  const auto b = camera.lens().ray(Eigen::Vector2d(k.cx + 1.0, k.cy));
  if (!a || !b) return 0.0;
  return std::acos(std::clamp(a->normalized().dot(b->normalized()), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

void apply_uncertainty_bound(PoleEstimate& e, double max_cone95_deg) {
  if (!e.valid || !std::isfinite(max_cone95_deg)) return;
  if (e.cone95_deg > max_cone95_deg) {
    e.valid = false;
    e.why_invalid = "uncertainty above the bound: 95 % cone " + deg_text(e.cone95_deg) + " > " +
                    deg_text(max_cone95_deg) + " (σ bearing " + deg_text(e.sigma_bearing_deg) +
                    ", σ latitude " + deg_text(e.sigma_latitude_deg) + ")";
  }
}

}  // namespace skypol::skypole
