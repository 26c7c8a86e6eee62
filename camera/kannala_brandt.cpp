// Kannala–Brandt (OpenCV fisheye) forward map and its safeguarded-Newton inverse.
#include "camera/kannala_brandt.h"
#include "camera/detail/lens_checks.h"
#include "camera/lens_registry.h"

#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "camera/detail/radial_util.h"
#include "camera/detail/ray_table.h"

namespace skypol::camera {
namespace {

// The smallest θ in (0, θmax] where dθd/dθ = g(θ²) stops being positive, g(u) = 1 + 3k1·u +
// 5k2·u² + 7k3·u³ + 9k4·u⁴. The dense scan finds sign changes; the quartic's real roots (companion
// matrix eigenvalues) also catch a dip between two scan samples and a touching double root.
std::optional<double> turning_point(const std::array<double, 4>& k, double theta_max,
                                    const std::function<double(double)>& dtheta_d) {
  std::optional<double> turn = detail::first_turning_point(dtheta_d, theta_max);
  const std::array<double, 5> c = {1, 3 * k[0], 5 * k[1], 7 * k[2], 9 * k[3]};
  int deg = 4;
  while (deg > 0 && c[deg] == 0) --deg;
  if (deg == 0) return turn;
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(deg, deg);
  for (int i = 0; i < deg; ++i) companion(0, i) = -c[deg - 1 - i] / c[deg];
  for (int i = 1; i < deg; ++i) companion(i, i - 1) = 1;
  const Eigen::VectorXcd roots = companion.eigenvalues();
  const double umax = theta_max * theta_max;
  for (Eigen::Index i = 0; i < roots.size(); ++i) {
    const double u = roots[i].real();
    if (!(u > 0 && u <= umax * (1 + 1e-12))) continue;
    const double t = std::sqrt(std::min(u, umax));
    // A real root, or the near-real pair of a (near-)double root: g is ~0 there.
    if (dtheta_d(t) <= 1e-9 && (!turn || t < *turn)) turn = t;
  }
  return turn;
}

}  // namespace

KannalaBrandtLens::KannalaBrandtLens(Intrinsics intrinsics, std::array<double, 4> k,
                                     double max_field_angle, OnTurnover on_turnover)
    : k_(intrinsics), coef_(k), theta_max_(max_field_angle) {
  detail::check_intrinsics(k_);
  for (std::size_t i = 0; i < coef_.size(); ++i)
    if (!std::isfinite(coef_[i]))
      throw std::invalid_argument("k" + std::to_string(i + 1) + " must be finite");
  if (!(std::isfinite(theta_max_) && theta_max_ > 0 && theta_max_ <= std::numbers::pi))
    throw std::invalid_argument("field of view must be in (0°, 360°]");
  const auto turn =
      turning_point(coef_, theta_max_, [this](double t) { return distorted_derivative(t); });
  if (turn) {
    if (on_turnover == OnTurnover::reject || *turn <= 0)
      throw std::invalid_argument(
          "distortion curve not monotone over the declared field of view (turns over at " +
          detail::format_deg(*turn) + ")");
    theta_max_ = *turn;
  }
  r_max_ = distorted(theta_max_);
  table_ = std::make_shared<const detail::LazyRadialTable>(
      [k = coef_, t = theta_max_] { return detail::odd_polynomial_table(k, t); });
}

double KannalaBrandtLens::distorted(double t) const {
  const double t2 = t * t;
  return t * (1 + t2 * (coef_[0] + t2 * (coef_[1] + t2 * (coef_[2] + t2 * coef_[3]))));
}

double KannalaBrandtLens::distorted_derivative(double t) const {
  const double t2 = t * t;
  return 1 + t2 * (3 * coef_[0] + t2 * (5 * coef_[1] + t2 * (7 * coef_[2] + t2 * 9 * coef_[3])));
}

std::optional<Eigen::Vector2d> KannalaBrandtLens::project(const Eigen::Vector3d& dir_cam) const {
  return detail::project_radial(k_, theta_max_, dir_cam, [this](double t) { return distorted(t); });
}

std::optional<Eigen::Vector3d> KannalaBrandtLens::ray(const Eigen::Vector2d& pixel) const {
  const auto m = detail::normalized_within(k_, pixel, r_max_);
  if (!m) return std::nullopt;
  const auto [mx, my, r] = *m;
  if (r == 0) return Eigen::Vector3d(0, 0, 1);
  const auto theta = detail::solve_increasing([this](double t) { return distorted(t); },
                                              [this](double t) { return distorted_derivative(t); },
                                              std::min(r, r_max_), 0.0, theta_max_, r);
  if (!theta) return std::nullopt;
  return detail::direction(*theta, mx, my, r);
}

void KannalaBrandtLens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                                unsigned char* valid) const {
  const auto& c = coef_;
  // θd(θ) and its derivative as in distorted() and distorted_derivative(), inlined.
  const auto fwd = [c](double t, double& r, double& dr) {
    const double t2 = t * t;
    r = t * (1 + t2 * (c[0] + t2 * (c[1] + t2 * (c[2] + t2 * c[3]))));
    dr = 1 + t2 * (3 * c[0] + t2 * (5 * c[1] + t2 * (7 * c[2] + t2 * 9 * c[3])));
  };
  const detail::RadialTable* table = table_->get();
  if (!table) return Lens::ray_row(y, x0, n, dx, dy, dz, valid);  // not expected: θd rises up to θmax
  detail::tabulated_ray_row(k_, *table, theta_max_, fwd, [this](const Eigen::Vector2d& p) { return ray(p); }, y, x0,
                            n, dx, dy, dz, valid);
}

std::shared_ptr<const Lens> KannalaBrandtLens::rescaled(double s) const {
  // The turning point, if clamped, is already in theta_max_; it is monotone there by construction.
  return std::make_shared<KannalaBrandtLens>(detail::rescale_intrinsics(k_, s), coef_, theta_max_,
                                             OnTurnover::clamp_fov);
}

std::vector<std::pair<std::string, double>> KannalaBrandtLens::parameters() const {
  auto p = Lens::parameters();
  for (std::size_t i = 0; i < coef_.size(); ++i) {
    std::string key = "k";
    key += std::to_string(i + 1);
    p.emplace_back(key, coef_[i]);
  }
  return p;
}

LensModel kannala_brandt_lens_model() {
  LensModel m;
  m.name = "kannala_brandt";
  m.description = "θ_d = θ(1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸) (OpenCV fisheye, COLMAP OPENCV_FISHEYE)";
  m.fields = {LensField::coefficients, LensField::clamp_fov_to_monotone};
  m.make = [](const LensSpec& s) -> std::shared_ptr<const Lens> {
    if (s.coefficients.size() != 4)
      detail::lens_fail("coefficients: kannala_brandt needs 4 (k1 k2 k3 k4), got " + std::to_string(s.coefficients.size()));
    return std::make_shared<KannalaBrandtLens>(
        detail::pinhole_intrinsics(s),
        std::array<double, 4>{s.coefficients[0], s.coefficients[1], s.coefficients[2], s.coefficients[3]},
        detail::half_fov(s, true),
        s.clamp_fov_to_monotone ? KannalaBrandtLens::OnTurnover::clamp_fov : KannalaBrandtLens::OnTurnover::reject);
  };
  return m;
}

}  // namespace skypol::camera
