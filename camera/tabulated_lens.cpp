// Fritsch–Carlson monotone cubic interpolation of a lens' image height curve, both ways.
#include "camera/tabulated_lens.h"
#include "camera/detail/lens_checks.h"
#include "camera/lens_registry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "camera/detail/radial_util.h"
#include "sky/units.h"

namespace skypol::camera {

HeightTable height_table_from_deg_mm(const std::vector<std::pair<double, double>>& deg_mm) {
  HeightTable t;
  for (const auto& [deg, mm] : deg_mm) {
    t.theta.push_back(rad_from_deg(deg));
    t.height.push_back(mm);
  }
  return t;
}

TabulatedLens::TabulatedLens(Intrinsics intrinsics, HeightTable table)
    : k_(intrinsics), t_(std::move(table)) {
  detail::check_intrinsics(k_);
  if (t_.theta.size() != t_.height.size())
    throw std::invalid_argument("image height table: angle and height columns differ in length");
  for (std::size_t i = 0; i < t_.theta.size(); ++i)
    if (!std::isfinite(t_.theta[i]) || !std::isfinite(t_.height[i]))
      throw std::invalid_argument("image height table: entries must be finite");
  if (!t_.theta.empty() && t_.theta.front() < 0)
    throw std::invalid_argument("image height table: field angles must be >= 0");
  if (!t_.theta.empty() && t_.theta.front() == 0 && t_.height.front() != 0)
    throw std::invalid_argument("image height table: height at 0° must be 0");
  if (t_.theta.empty() || t_.theta.front() > 0) {
    t_.theta.insert(t_.theta.begin(), 0.0);
    t_.height.insert(t_.height.begin(), 0.0);
  }
  const std::size_t n = t_.theta.size();
  if (n < 2) throw std::invalid_argument("image height table needs at least one point beyond 0°");
  for (std::size_t i = 1; i < n; ++i) {
    if (!(t_.theta[i] > t_.theta[i - 1]))
      throw std::invalid_argument("image height table: field angles not strictly ascending at " +
                                  detail::format_deg(t_.theta[i]));
    if (!(t_.height[i] > t_.height[i - 1]))
      throw std::invalid_argument("image height table not monotone at " +
                                  detail::format_deg(t_.theta[i]));
  }
  if (t_.theta.back() > std::numbers::pi)
    throw std::invalid_argument("image height table: field angle beyond 180°");

  // Fritsch–Carlson: second-order (parabola through three points) tangents, one-sided at the
  // ends and kept ≥ 0 there, then limited to α² + β² ≤ 9 per segment, which makes every segment's
  // cubic monotone. The second-order start keeps a smooth curve accurate to O(h³).
  std::vector<double> h(n - 1), delta(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = t_.theta[i + 1] - t_.theta[i];
    delta[i] = (t_.height[i + 1] - t_.height[i]) / h[i];
  }
  slope_.assign(n, 0.0);
  if (n == 2) {
    slope_[0] = slope_[1] = delta[0];
  } else {
    for (std::size_t i = 1; i + 1 < n; ++i)
      slope_[i] = (h[i] * delta[i - 1] + h[i - 1] * delta[i]) / (h[i - 1] + h[i]);
    slope_[0] = std::max(0.0, ((2 * h[0] + h[1]) * delta[0] - h[0] * delta[1]) / (h[0] + h[1]));
    const std::size_t m = n - 2;
    slope_[n - 1] =
        std::max(0.0, ((2 * h[m] + h[m - 1]) * delta[m] - h[m] * delta[m - 1]) / (h[m] + h[m - 1]));
  }
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double a = slope_[i] / delta[i], b = slope_[i + 1] / delta[i];
    const double s = a * a + b * b;
    if (s > 9) {
      const double tau = 3 / std::sqrt(s);
      slope_[i] = tau * a * delta[i];
      slope_[i + 1] = tau * b * delta[i];
    }
  }
}

std::size_t TabulatedLens::segment_of_theta(double theta) const {
  const auto it = std::upper_bound(t_.theta.begin(), t_.theta.end(), theta);
  const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - t_.theta.begin() - 1, 0));
  return std::min(i, t_.theta.size() - 2);
}

double TabulatedLens::hermite(std::size_t i, double theta) const {
  const double h = t_.theta[i + 1] - t_.theta[i];
  const double s = (theta - t_.theta[i]) / h;
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * t_.height[i] + (s3 - 2 * s2 + s) * h * slope_[i] +
         (-2 * s3 + 3 * s2) * t_.height[i + 1] + (s3 - s2) * h * slope_[i + 1];
}

double TabulatedLens::hermite_derivative(std::size_t i, double theta) const {
  const double h = t_.theta[i + 1] - t_.theta[i];
  const double s = (theta - t_.theta[i]) / h;
  const double s2 = s * s;
  return ((6 * s2 - 6 * s) * t_.height[i] + (6 * s - 6 * s2) * t_.height[i + 1]) / h +
         (3 * s2 - 4 * s + 1) * slope_[i] + (3 * s2 - 2 * s) * slope_[i + 1];
}

double TabulatedLens::height(double theta) const {
  const double t = std::clamp(theta, 0.0, t_.theta.back());
  return hermite(segment_of_theta(t), t);
}

double TabulatedLens::angle(double h) const {
  const double r = std::clamp(h, 0.0, t_.height.back());
  const auto it = std::upper_bound(t_.height.begin(), t_.height.end(), r);
  std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - t_.height.begin() - 1, 0));
  i = std::min(i, t_.height.size() - 2);
  const double lo = t_.theta[i], hi = t_.theta[i + 1];
  const double guess = lo + (hi - lo) * (r - t_.height[i]) / (t_.height[i + 1] - t_.height[i]);
  // The segment's cubic is monotone (Fritsch–Carlson) and takes the table values at its ends,
  // so the bracket always holds; the fallback only guards rounding.
  const auto theta = detail::solve_increasing([&](double x) { return hermite(i, x); },
                                              [&](double x) { return hermite_derivative(i, x); },
                                              r, lo, hi, guess);
  return theta ? *theta : guess;
}

std::optional<Eigen::Vector2d> TabulatedLens::project(const Eigen::Vector3d& dir_cam) const {
  return detail::project_radial(k_, t_.theta.back(), dir_cam, [this](double t) { return height(t); });
}

std::optional<Eigen::Vector3d> TabulatedLens::ray(const Eigen::Vector2d& pixel) const {
  const auto m = detail::normalized_within(k_, pixel, t_.height.back());
  if (!m) return std::nullopt;
  return detail::direction(angle(m->r), m->mx, m->my, m->r);
}

void TabulatedLens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                            unsigned char* valid) const {
  detail::radial_ray_row(k_, t_.height.back(), [this](double r) { return angle(r); }, y, x0, n, dx, dy, dz, valid);
}

std::shared_ptr<const Lens> TabulatedLens::rescaled(double s) const {
  return std::make_shared<TabulatedLens>(detail::rescale_intrinsics(k_, s), t_);
}

std::vector<std::pair<std::string, double>> TabulatedLens::parameters() const {
  auto p = Lens::parameters();
  for (std::size_t i = 0; i < t_.theta.size(); ++i) {
    std::string angle_key = "theta_deg_", height_key = "height_";
    angle_key += std::to_string(i);
    height_key += std::to_string(i);
    p.emplace_back(angle_key, deg_from_rad(t_.theta[i]));
    p.emplace_back(height_key, t_.height[i]);
  }
  return p;
}

LensModel tabulated_lens_model() {
  LensModel m;
  m.name = "tabulated";
  m.description = "a lens maker's table of image height (mm) against field angle (deg), pitch_um to pixels";
  m.fields = {LensField::table};
  m.pitch_converts_mm = true;
  m.make = [](const LensSpec& s) -> std::shared_ptr<const Lens> {
    if (s.fx.has_value() || s.fy.has_value()) detail::lens_fail("fx/fy: not used by model " + s.model);
    if (s.focal_mm.has_value()) detail::lens_fail("focal_mm: not used by model " + s.model);
    if (s.table.empty()) detail::lens_fail("table: tabulated needs (field angle deg, image height mm) rows");
    if (!s.pitch_um) detail::lens_fail("pitch_um is required for model tabulated");
    LensSpec px = s;  // reuse the pinhole checks with 1 mm of image height = 1/pitch pixels
    px.focal_mm = 1.0;
    Intrinsics k = detail::pinhole_intrinsics(px);
    HeightTable t = height_table_from_deg_mm(s.table);
    const double tmax = detail::half_fov(s, false);
    if (tmax > 0) {
      if (t.theta.empty() || tmax > t.theta.back() * (1 + 1e-12))
        detail::lens_fail("fov_deg " + detail::lens_number(*s.fov_deg) + " exceeds the table's last field angle");
      const TabulatedLens full(k, t);  // checks the table; then cut it at tmax
      const double h = full.height(tmax);
      HeightTable cut;
      for (std::size_t i = 0; i < t.theta.size() && t.theta[i] < tmax; ++i) {
        cut.theta.push_back(t.theta[i]);
        cut.height.push_back(t.height[i]);
      }
      cut.theta.push_back(tmax);
      cut.height.push_back(h);
      t = cut;
    }
    return std::make_shared<TabulatedLens>(k, t);
  };
  return m;
}

}  // namespace skypol::camera
