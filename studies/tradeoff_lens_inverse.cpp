// Study 5a: the lens inverse. A Kannala–Brandt fisheye (the equisolid projection's Taylor series
// as k1..k4: strongly non-linear at 92.5°) on the paper's sensor; its pixel → ray inverse solved by
// Newton from θ = r with a fixed number of iterations, or until the step is below a tolerance,
// against the library's bracketed Newton (camera/kannala_brandt.h, converged to 1e-15) and the
// paper's equidistant lens, whose inverse is closed form. Round-trip error = |project(ray(p)) − p|
// in pixels; time per ray on one thread. The library's inverse has no tolerance knob: this study
// says what one would buy.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "camera/kannala_brandt.h"
#include "camera/lens_factory.h"
#include "camera/presets.h"
#include "sky/units.h"
#include "studies/tradeoff_studies.h"
#include "studies/tradeoff_table.h"

namespace skypol::studies::tradeoff {
namespace {

struct Inverse {
  double theta;
  int iterations;
};

// θ with θd(θ) = r by plain Newton from θ = r, clamped to [0, θmax].
Inverse newton(const camera::KannalaBrandtLens& lens, double r, int max_iterations, double tolerance) {
  double t = std::min(r, lens.max_field_angle());
  int i = 0;
  for (; i < max_iterations; ++i) {
    const double step = (lens.distorted(t) - r) / lens.distorted_derivative(t);
    t = std::clamp(t - step, 0.0, lens.max_field_angle());
    if (std::abs(step) <= tolerance) {
      ++i;
      break;
    }
  }
  return {t, i};
}

Eigen::Vector3d direction(double theta, double mx, double my, double r) {
  if (r == 0) return Eigen::Vector3d::UnitZ();
  const double s = std::sin(theta) / r;
  return {s * mx, s * my, std::cos(theta)};
}

struct Measured {
  double ns_per_ray = 0, rms_px = 0, max_px = 0, mean_iterations = 0;
};

// Times `inverse` over the pixels (best of 3, one thread), then measures the round trip.
template <class Inv>
Measured measure(const camera::Lens& lens, const std::vector<Eigen::Vector2d>& pixels, Inv&& inverse) {
  std::vector<Eigen::Vector3d> rays(pixels.size());
  std::vector<int> iterations(pixels.size(), 0);
  const double s = best_seconds(3, [&] {
    for (std::size_t i = 0; i < pixels.size(); ++i) rays[i] = inverse(pixels[i], iterations[i]);
  });
  Measured m;
  m.ns_per_ray = 1e9 * s / static_cast<double>(pixels.size());
  double ss = 0, it = 0;
  bool counted = true;  // an inverse that cannot count its iterations reports −1
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const auto back = lens.project(rays[i]);
    const double e = back ? (*back - pixels[i]).norm() : 1e9;  // cannot happen inside the circle
    ss += e * e;
    m.max_px = std::max(m.max_px, e);
    it += iterations[i];
    counted = counted && iterations[i] >= 0;
  }
  m.rms_px = std::sqrt(ss / static_cast<double>(pixels.size()));
  m.mean_iterations = counted ? it / static_cast<double>(pixels.size()) : std::nan("");
  return m;
}

}  // namespace

void study_lens_inverse(const StudyOptions& o) {
  camera::Intrinsics k;
  k.width = 2448;
  k.height = 2048;
  k.fx = k.fy = 700;  // 2·sin(92.5°/2)·700 = 1012 px: the image circle fits the 2048 rows
  k.cx = 0.5 * (k.width - 1);
  k.cy = 0.5 * (k.height - 1);
  // 2 sin(θ/2) = θ (1 − θ²/24 + θ⁴/1920 − θ⁶/322560 + θ⁸/92897280 − …)
  const camera::KannalaBrandtLens kb(k, {-1.0 / 24, 1.0 / 1920, -1.0 / 322560, 1.0 / 92897280}, 92.5 * kRadPerDeg);
  const int step = o.small ? 64 : 4;
  std::vector<Eigen::Vector2d> pixels;
  for (int y = 0; y < k.height; y += step)
    for (int x = 0; x < k.width; x += step)
      if (kb.ray(Eigen::Vector2d(x, y))) pixels.emplace_back(x, y);
  const double full_frame_rays = static_cast<double>(k.width) * k.height;

  Table t({"lens", "mode", "max_iterations", "tolerance_rad", "mean_iterations", "ns_per_ray", "ms_per_full_frame",
           "roundtrip_rms_px", "roundtrip_max_px", "rays", "is_default"});
  auto add = [&](const std::string& lens, const std::string& mode, int max_it, double tol, const Measured& m,
                 bool is_default) {
    t.row()
        .set("lens", lens)
        .set("mode", mode)
        .set("max_iterations", max_it)
        .set("tolerance_rad", tol)
        .set("mean_iterations", m.mean_iterations)
        .set("ns_per_ray", m.ns_per_ray)
        .set("ms_per_full_frame", m.ns_per_ray * full_frame_rays * 1e-6)
        .set("roundtrip_rms_px", m.rms_px)
        .set("roundtrip_max_px", m.max_px)
        .set("rays", static_cast<int>(pixels.size()))
        .set("is_default", is_default);
  };
  auto kb_inverse = [&](int max_it, double tol) {
    return [&kb, &k, max_it, tol](const Eigen::Vector2d& p, int& its) {
      const double mx = (p.x() - k.cx) / k.fx, my = (p.y() - k.cy) / k.fy;
      const double r = std::hypot(mx, my);
      const Inverse inv = newton(kb, r, max_it, tol);
      its = inv.iterations;
      return direction(inv.theta, mx, my, r);
    };
  };
  for (const int n : {0, 1, 2, 3, 4, 5, 6, 8})
    add("kannala_brandt", "iterations", n, std::nan(""), measure(kb, pixels, kb_inverse(n, -1)), false);
  for (const double tol : {1e-3, 1e-5, 1e-7, 1e-9, 1e-12})
    add("kannala_brandt", "tolerance", 50, tol, measure(kb, pixels, kb_inverse(50, tol)), false);
  add("kannala_brandt", "library", 200, 1e-15, measure(kb, pixels, [&](const Eigen::Vector2d& p, int& its) {
        its = -1;
        return kb.ray(p).value_or(Eigen::Vector3d::UnitZ());
      }), true);

  // The paper's lens: equidistant, inverse in closed form (θ = r).
  const auto eq = camera::make_lens(camera::lens_spec(camera::lens_preset("fujinon_fe185c057ha1"),
                                                      camera::sensor_preset("sony_imx250mzr")));
  std::vector<Eigen::Vector2d> eq_pixels;
  for (int y = 0; y < k.height; y += step)
    for (int x = 0; x < k.width; x += step)
      if (eq->ray(Eigen::Vector2d(x, y))) eq_pixels.emplace_back(x, y);
  pixels = eq_pixels;
  add("equidistant", "closed_form", 0, std::nan(""), measure(*eq, pixels, [&](const Eigen::Vector2d& p, int& its) {
        its = -1;
        return eq->ray(p).value_or(Eigen::Vector3d::UnitZ());
      }), true);
  t.write((std::filesystem::path(o.out_dir) / "lens_inverse.csv").string());
}

}  // namespace skypol::studies::tradeoff
