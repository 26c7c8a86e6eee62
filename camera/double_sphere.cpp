// Double sphere projection and its closed-form unprojection (Usenko et al. 2018).
#include "camera/double_sphere.h"
#include "camera/detail/lens_checks.h"
#include "camera/lens_registry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "camera/detail/radial_util.h"
#include "camera/detail/ray_table.h"

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

namespace {

// Eqs. 46–47 for one pixel, shared by ray() and ray_row (the same bits): the unit direction in
// (x, y, z) and whether the pixel has one. Every lane is computed (square roots of max(·, 0)), so
// a loop over pixels has no branch.
struct Unproject {
  Intrinsics k;
  double xi, a, limit;
  bool operator()(double u, double v, double& x, double& y, double& z) const {
    const double mx = (u - k.cx) / k.fx, my = (v - k.cy) / k.fy;
    const double r2 = mx * mx + my * my;
    const double s1 = 1 - (2 * a - 1) * r2;  // eq. 46 validity: ≥ 0
    const double mz = (1 - a * a * r2) / (a * std::sqrt(std::max(s1, 0.0)) + 1 - a);
    const double s2 = mz * mz + (1 - xi * xi) * r2;
    const double kk = (mz * xi + std::sqrt(std::max(s2, 0.0))) / (mz * mz + r2);
    const double dx = kk * mx, dy = kk * my, dz = kk * mz - xi;
    const double n = std::sqrt(dx * dx + dy * dy + dz * dz);
    x = dx / n, y = dy / n, z = dz / n;
    return (std::sqrt(r2) <= limit) & (s1 >= 0) & (s2 >= 0) & (n > 0) & (n < HUGE_VAL);  // no short circuit: no branch
  }
};

}  // namespace

std::optional<Eigen::Vector3d> DoubleSphereLens::ray(const Eigen::Vector2d& pixel) const {
  if (!pixel.allFinite()) return std::nullopt;
  Eigen::Vector3d d;
  if (!Unproject{k_, xi_, alpha_, r_max_ * (1 + detail::kEdgeTol)}(pixel.x(), pixel.y(), d.x(), d.y(), d.z()))
    return std::nullopt;
  return d;
}

void DoubleSphereLens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                               unsigned char* valid) const {
  detail::closed_form_ray_row(Unproject{k_, xi_, alpha_, r_max_ * (1 + detail::kEdgeTol)}, y, x0, n, dx, dy, dz,
                              valid);
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

LensModel double_sphere_lens_model() {
  LensModel m;
  m.name = "double_sphere";
  m.description = "Usenko et al.'s double sphere (xi alpha)";
  m.fields = {LensField::coefficients};
  m.make = [](const LensSpec& s) -> std::shared_ptr<const Lens> {
    if (s.coefficients.size() != 2)
      detail::lens_fail("coefficients: double_sphere needs 2 (xi alpha), got " + std::to_string(s.coefficients.size()));
    return std::make_shared<DoubleSphereLens>(detail::pinhole_intrinsics(s), s.coefficients[0], s.coefficients[1],
                                              detail::half_fov(s, true));
  };
  return m;
}

}  // namespace skypol::camera
