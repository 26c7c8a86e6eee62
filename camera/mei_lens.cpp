// Mei's unified model (cv::omnidir): closed-form projection, Newton undistortion, closed-form lift.
#include "camera/mei_lens.h"
#include "camera/detail/lens_checks.h"
#include "camera/lens_registry.h"
#include <array>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "camera/detail/distortion_2d.h"
#include "camera/detail/radial_util.h"
#include "camera/detail/ray_table.h"

namespace skypol::camera {
namespace {

// Radial-tangential distortion of an undistorted point (OpenCV's order k1, k2, p1, p2).
detail::Distorted distort(const std::array<double, 4>& c, const Eigen::Vector2d& p) {
  const auto [k1, k2, p1, p2] = c;
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (k1 + r2 * k2);
  const double dradial = k1 + 2 * k2 * r2;  // d(radial)/d(r²)
  detail::Distorted d;
  d.q = {x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x), y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y};
  d.jacobian << radial + 2 * x * x * dradial + 2 * p1 * y + 6 * p2 * x, 2 * x * y * dradial + 2 * p1 * x + 2 * p2 * y,
      2 * x * y * dradial + 2 * p1 * x + 2 * p2 * y, radial + 2 * y * y * dradial + 6 * p1 * y + 2 * p2 * x;
  return d;
}

}  // namespace

double MeiLens::valid_angle(double xi) {
  // ξ ≤ 1: the denominator cos θ + ξ reaches 0 at acos(−ξ); ξ > 1: r(θ) turns over at acos(−1/ξ).
  return std::acos(-std::min(xi, xi > 0 ? 1 / xi : 0.0));
}

MeiLens::MeiLens(Intrinsics intrinsics, double skew, double xi, std::array<double, 4> distortion,
                 double max_field_angle)
    : k_(intrinsics), skew_(skew), xi_(xi), dist_(distortion), theta_max_(max_field_angle) {
  detail::check_intrinsics(k_);
  if (!std::isfinite(skew_)) throw std::invalid_argument("skew must be finite");
  if (!(std::isfinite(xi_) && xi_ >= 0)) throw std::invalid_argument("xi must be >= 0");
  for (double v : dist_)
    if (!std::isfinite(v)) throw std::invalid_argument("coefficients must be finite");
  if (!(std::isfinite(theta_max_) && theta_max_ > 0)) throw std::invalid_argument("field of view must be > 0");
  const double limit = valid_angle(xi_);
  if (theta_max_ >= limit)
    throw std::invalid_argument("field of view (half-angle " + detail::format_deg(theta_max_) +
                                ") exceeds the unified (Mei) model's limit of " + detail::format_deg(limit) +
                                " for xi = " + std::to_string(xi_));
  r_max_ = radius(theta_max_);
  if (const auto fold = detail::first_fold([this](const Eigen::Vector2d& p) { return distort(dist_, p); }, r_max_)) {
    // Report the fold as an angle: invert r(θ) = sin θ/(cos θ + ξ) by bisection.
    double lo = 0, hi = theta_max_;
    for (int i = 0; i < 100; ++i) (radius(0.5 * (lo + hi)) < *fold ? lo : hi) = 0.5 * (lo + hi);
    throw std::invalid_argument("radial-tangential distortion not one-to-one over the declared field of view (folds at " +
                                detail::format_deg(lo) + ")");
  }
  // The radial part ρ·(1 + k1ρ² + k2ρ⁴) alone, inverted by a table, starts ray_row's Newton steps.
  table_ = std::make_shared<const detail::LazyRadialTable>([d = dist_, r = r_max_] {
    return detail::odd_polynomial_table({d[0], d[1], 0, 0}, r);
  });
}

void MeiLens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                      unsigned char* valid) const {
  const detail::RadialTable* table = table_->get();
  if (!table) return Lens::ray_row(y, x0, n, dx, dy, dz, valid);
  const auto [k1, k2, p1, p2] = dist_;
  const Intrinsics k = k_;
  const double skew = skew_, xi = xi_, r_max = r_max_;
  const auto norm = [k, skew](double u, double v, double& mx, double& my) {
    my = (v - k.cy) / k.fy;
    mx = (u - k.cx - skew * my) / k.fx;
  };
  // distort() of the anonymous namespace, its Eigen types spelled out as scalars.
  const auto dist = [=](double a, double b, double& qa, double& qb, double* j) {
    const double r2 = a * a + b * b;
    const double radial = 1 + r2 * (k1 + r2 * k2);
    const double dradial = k1 + 2 * k2 * r2;
    qa = a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a);
    qb = b * radial + p1 * (r2 + 2 * b * b) + 2 * p2 * a * b;
    j[0] = radial + 2 * a * a * dradial + 2 * p1 * b + 6 * p2 * a;
    j[1] = 2 * a * b * dradial + 2 * p1 * a + 2 * p2 * b;
    j[2] = j[1];
    j[3] = radial + 2 * b * b * dradial + 6 * p1 * b + 2 * p2 * a;
  };
  // ray()'s lift to the sphere (Mei & Rives eq. 5).
  const auto lift = [xi, r_max](double px, double py, double pr, double& ox, double& oy, double& oz) {
    const double r2 = pr * pr;
    const double disc = 1 + (1 - xi * xi) * detail::vmin(r2, r_max * r_max);
    const double lambda = (xi + std::sqrt(detail::vmax(disc, 0.0))) / (1 + r2);
    const double a = lambda * px, b = lambda * py, c = lambda - xi;
    const double len = std::sqrt(a * a + b * b + c * c);
    ox = a / len, oy = b / len, oz = c / len;
    return (disc >= 0) & (len > 0) & (len < HUGE_VAL);
  };
  detail::undistort_ray_row(*table, r_max_, norm, dist, lift, [this](const Eigen::Vector2d& p) { return ray(p); }, y,
                            x0, n, dx, dy, dz, valid);
}

double MeiLens::radius(double theta) const { return std::sin(theta) / (std::cos(theta) + xi_); }

std::optional<Eigen::Vector2d> MeiLens::project(const Eigen::Vector3d& dir_cam) const {
  const auto p = detail::polar_of(dir_cam);
  if (!p || p->theta > theta_max_ + detail::kEdgeTol) return std::nullopt;
  const double r = radius(std::min(p->theta, theta_max_));
  const Eigen::Vector2d q = distort(dist_, {r * p->c, r * p->s}).q;
  return Eigen::Vector2d(k_.fx * q.x() + skew_ * q.y() + k_.cx, k_.fy * q.y() + k_.cy);
}

std::optional<Eigen::Vector3d> MeiLens::ray(const Eigen::Vector2d& pixel) const {
  if (!pixel.allFinite()) return std::nullopt;
  const double yd = (pixel.y() - k_.cy) / k_.fy;
  const Eigen::Vector2d m((pixel.x() - k_.cx - skew_ * yd) / k_.fx, yd);
  const auto p = detail::undistort_2d([this](const Eigen::Vector2d& x) { return distort(dist_, x); }, m, m);
  if (!p) return std::nullopt;
  const double r2 = p->squaredNorm();
  if (std::sqrt(r2) > r_max_ * (1 + detail::kEdgeTol)) return std::nullopt;
  const double disc = 1 + (1 - xi_ * xi_) * std::min(r2, r_max_ * r_max_);
  if (disc < 0) return std::nullopt;
  const double lambda = (xi_ + std::sqrt(disc)) / (1 + r2);
  const Eigen::Vector3d d(lambda * p->x(), lambda * p->y(), lambda - xi_);
  const double n = d.norm();
  if (!(n > 0) || !std::isfinite(n)) return std::nullopt;
  return Eigen::Vector3d(d / n);
}

std::shared_ptr<const Lens> MeiLens::rescaled(double s) const {
  return std::make_shared<MeiLens>(detail::rescale_intrinsics(k_, s), skew_ * s, xi_, dist_, theta_max_);
}

std::vector<std::pair<std::string, double>> MeiLens::parameters() const {
  auto p = Lens::parameters();
  p.emplace_back("skew", skew_);
  p.emplace_back("xi", xi_);
  const char* names[] = {"k1", "k2", "p1", "p2"};
  for (std::size_t i = 0; i < dist_.size(); ++i) p.emplace_back(names[i], dist_[i]);
  return p;
}

LensModel mei_lens_model() {
  LensModel m;
  m.name = "mei";
  m.description = "Mei's unified model, cv::omnidir (xi k1 k2 p1 p2, skew)";
  m.fields = {LensField::coefficients, LensField::skew};
  m.make = [](const LensSpec& s) -> std::shared_ptr<const Lens> {
    detail::need_coefficients(s, 5, "xi k1 k2 p1 p2");
    const auto& c = s.coefficients;
    return std::make_shared<MeiLens>(detail::pinhole_intrinsics(s), s.skew.value_or(0.0), c[0],
                                     std::array<double, 4>{c[1], c[2], c[3], c[4]}, detail::half_fov(s, true));
  };
  return m;
}

}  // namespace skypol::camera
