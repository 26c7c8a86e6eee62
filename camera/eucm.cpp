// EUCM projection and its closed-form unprojection (eucm.h).
#include "camera/eucm.h"
#include "camera/detail/lens_checks.h"
#include "camera/lens_registry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "camera/detail/radial_util.h"
#include "camera/detail/ray_table.h"
#include "sky/units.h"

namespace skypol::camera {

EucmLens::EucmLens(Intrinsics intrinsics, double alpha, double beta, double max_field_angle)
    : k_(intrinsics), alpha_(alpha), beta_(beta), theta_max_(max_field_angle) {
  detail::check_intrinsics(k_);
  if (!(std::isfinite(alpha_) && alpha_ >= 0 && alpha_ <= 1)) throw std::invalid_argument("alpha must be in [0, 1]");
  if (!(std::isfinite(beta_) && beta_ > 0)) throw std::invalid_argument("beta must be > 0");
  if (!(std::isfinite(theta_max_) && theta_max_ > 0 && theta_max_ < kPi))
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

namespace {

// The closed-form unprojection (eucm.h) for one pixel, shared by ray() and ray_row (the same
// bits); every lane computed, so a loop over pixels has no branch.
struct Unproject {
  Intrinsics k;
  double a, b, r_max, limit;
  bool operator()(double u, double v, double& x, double& y, double& z) const {
    const double mx = (u - k.cx) / k.fx, my = (v - k.cy) / k.fy;
    const double m2 = mx * mx + my * my;
    const double r2 = std::min(m2, r_max * r_max);
    const double s = 1 - (2 * a - 1) * b * r2;
    const double mz = (1 - b * a * a * r2) / (a * std::sqrt(std::max(s, 0.0)) + 1 - a);
    const double n = std::sqrt(m2 + mz * mz);
    x = mx / n, y = my / n, z = mz / n;
    return (std::sqrt(m2) <= limit) & (s >= 0) & (n > 0) & (n < HUGE_VAL);  // no short circuit: no branch
  }
};

}  // namespace

std::optional<Eigen::Vector3d> EucmLens::ray(const Eigen::Vector2d& pixel) const {
  if (!pixel.allFinite()) return std::nullopt;
  Eigen::Vector3d d;
  if (!Unproject{k_, alpha_, beta_, r_max_, r_max_ * (1 + detail::kEdgeTol)}(pixel.x(), pixel.y(), d.x(), d.y(), d.z()))
    return std::nullopt;
  return d;
}

void EucmLens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                       unsigned char* valid) const {
  detail::closed_form_ray_row(Unproject{k_, alpha_, beta_, r_max_, r_max_ * (1 + detail::kEdgeTol)}, y, x0, n, dx, dy,
                              dz, valid);
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

LensModel eucm_lens_model() {
  LensModel m;
  m.name = "eucm";
  m.description = "the enhanced unified camera model (alpha beta)";
  m.fields = {LensField::coefficients};
  m.make = [](const LensSpec& s) -> std::shared_ptr<const Lens> {
    detail::need_coefficients(s, 2, "alpha beta");
    return std::make_shared<EucmLens>(detail::pinhole_intrinsics(s), s.coefficients[0], s.coefficients[1],
                                      detail::half_fov(s, true));
  };
  return m;
}

}  // namespace skypol::camera
