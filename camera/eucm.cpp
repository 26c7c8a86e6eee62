// EUCM projection and its closed-form unprojection (eucm.h).
#include "camera/eucm.h"

#include <cmath>
#include <stdexcept>

#include "camera/detail/radial_util.h"

namespace skypol::camera {

EucmLens::EucmLens(Intrinsics intrinsics, double alpha, double beta, double max_field_angle)
    : k_(intrinsics), alpha_(alpha), beta_(beta), theta_max_(max_field_angle) {
  detail::check_intrinsics(k_);
  if (!(std::isfinite(alpha_) && alpha_ >= 0 && alpha_ <= 1)) throw std::invalid_argument("alpha must be in [0, 1]");
  if (!(std::isfinite(beta_) && beta_ > 0)) throw std::invalid_argument("beta must be > 0");
  if (!(std::isfinite(theta_max_) && theta_max_ > 0 && theta_max_ < 3.14159265358979323846))
    throw std::invalid_argument("field of view must be in (0, 360)");
  // The radius must rise (with a positive denominator) over the whole declared field.
  double prev = 0;
  for (int i = 1; i <= 4096; ++i) {
    const double t = theta_max_ * i / 4096;
    const double r = radius(t);
    if (!(std::isfinite(r) && r > prev))
      throw std::invalid_argument("EUCM curve not monotone over the declared field of view (turns over at " +
                                  detail::format_deg(t) + ")");
    prev = r;
  }
  r_max_ = radius(theta_max_);
  if (1 - (2 * alpha_ - 1) * beta_ * r_max_ * r_max_ < 0)
    throw std::invalid_argument("field of view exceeds the EUCM model's valid region");
}

double EucmLens::radius(double theta) const {
  const double st = std::sin(theta), ct = std::cos(theta);
  const double den = alpha_ * std::sqrt(beta_ * st * st + ct * ct) + (1 - alpha_) * ct;
  return den > 0 ? st / den : std::nan("");
}

std::optional<Eigen::Vector2d> EucmLens::project(const Eigen::Vector3d& dir_cam) const {
  return detail::project_radial(k_, theta_max_, dir_cam, [this](double t) { return radius(t); });
}

std::optional<Eigen::Vector3d> EucmLens::ray(const Eigen::Vector2d& pixel) const {
  const auto m = detail::normalized_within(k_, pixel, r_max_);
  if (!m) return std::nullopt;
  const auto [mx, my, r] = *m;
  const double r2 = std::min(r * r, r_max_ * r_max_);
  const double s = 1 - (2 * alpha_ - 1) * beta_ * r2;
  if (s < 0) return std::nullopt;
  const double mz = (1 - beta_ * alpha_ * alpha_ * r2) / (alpha_ * std::sqrt(s) + 1 - alpha_);
  const Eigen::Vector3d d(mx, my, mz);
  const double n = d.norm();
  if (!(n > 0) || !std::isfinite(n)) return std::nullopt;
  return Eigen::Vector3d(d / n);
}

std::shared_ptr<const Lens> EucmLens::rescaled(double s) const {
  return std::make_shared<EucmLens>(detail::rescale_intrinsics(k_, s), alpha_, beta_, theta_max_);
}

std::vector<std::pair<std::string, double>> EucmLens::parameters() const {
  auto p = Lens::parameters();
  p.emplace_back("alpha", alpha_);
  p.emplace_back("beta", beta_);
  return p;
}

}  // namespace skypol::camera
