// Double sphere projection and its closed-form unprojection (Usenko et al. 2018).
#include "camera/double_sphere.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "camera/detail/radial_util.h"

namespace skypol::camera {

double DoubleSphereLens::valid_angle(double xi, double alpha) {
  const double w1 = alpha <= 0.5 ? alpha / (1 - alpha) : (1 - alpha) / alpha;
  const double w2 = (w1 + xi) / std::sqrt(2 * w1 * xi + xi * xi + 1);
  return std::acos(std::clamp(-w2, -1.0, 1.0));
}

DoubleSphereLens::DoubleSphereLens(Intrinsics intrinsics, double xi, double alpha,
                                   double max_field_angle)
    : k_(intrinsics), xi_(xi), alpha_(alpha), theta_max_(max_field_angle) {
  detail::check_intrinsics(k_);
  if (!(std::isfinite(alpha_) && alpha_ >= 0 && alpha_ <= 1))
    throw std::invalid_argument("alpha must be in [0, 1]");
  if (!(std::isfinite(xi_) && xi_ > -1)) throw std::invalid_argument("xi must be > -1");
  if (!(std::isfinite(theta_max_) && theta_max_ > 0))
    throw std::invalid_argument("field of view must be > 0");
  const double limit = valid_angle(xi_, alpha_);
  if (theta_max_ >= limit)
    throw std::invalid_argument("field of view (half-angle " + detail::format_deg(theta_max_) +
                                ") exceeds the double sphere model's limit of " +
                                detail::format_deg(limit));
  // Inside the valid region the radius rises with θ; check it rather than trust it.
  double prev = 0;
  for (int i = 1; i <= 4096; ++i) {
    const double r = radius(theta_max_ * i / 4096);
    if (!(r > prev))
      throw std::invalid_argument("double sphere curve not monotone over the declared field of view (turns over at " +
                                  detail::format_deg(theta_max_ * i / 4096) + ")");
    prev = r;
  }
  r_max_ = radius(theta_max_);
}

double DoubleSphereLens::radius(double theta) const {
  const double st = std::sin(theta), ct = std::cos(theta);
  const double zs = xi_ + ct;  // unit direction: d1 = 1
  const double d2 = std::sqrt(st * st + zs * zs);
  return st / (alpha_ * d2 + (1 - alpha_) * zs);
}

std::optional<Eigen::Vector2d> DoubleSphereLens::project(const Eigen::Vector3d& dir_cam) const {
  return detail::project_radial(k_, theta_max_, dir_cam, [this](double t) { return radius(t); });
}

std::optional<Eigen::Vector3d> DoubleSphereLens::ray(const Eigen::Vector2d& pixel) const {
  const auto m = detail::normalized_within(k_, pixel, r_max_);
  if (!m) return std::nullopt;
  const auto [mx, my, r] = *m;
  const double r2 = r * r;
  const double a = alpha_;
  const double s1 = 1 - (2 * a - 1) * r2;  // eq. 46 validity: ≥ 0
  if (s1 < 0) return std::nullopt;
  const double mz = (1 - a * a * r2) / (a * std::sqrt(s1) + 1 - a);
  const double s2 = mz * mz + (1 - xi_ * xi_) * r2;
  if (s2 < 0) return std::nullopt;
  const double k = (mz * xi_ + std::sqrt(s2)) / (mz * mz + r2);
  const Eigen::Vector3d d(k * mx, k * my, k * mz - xi_);
  const double n = d.norm();
  if (!(n > 0) || !std::isfinite(n)) return std::nullopt;
  return Eigen::Vector3d(d / n);
}

std::shared_ptr<const Lens> DoubleSphereLens::rescaled(double s) const {
  return std::make_shared<DoubleSphereLens>(detail::rescale_intrinsics(k_, s), xi_, alpha_,
                                            theta_max_);
}

std::vector<std::pair<std::string, double>> DoubleSphereLens::parameters() const {
  auto p = Lens::parameters();
  p.emplace_back("xi", xi_);
  p.emplace_back("alpha", alpha_);
  return p;
}

}  // namespace skypol::camera
