// THIN_PRISM_FISHEYE: closed-form projection, Newton inverse (thin_prism_fisheye.h).
#include "camera/thin_prism_fisheye.h"
#include "camera/detail/lens_checks.h"
#include "camera/lens_registry.h"
#include <algorithm>
#include <array>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "camera/detail/distortion_2d.h"
#include "camera/detail/radial_util.h"
#include "camera/detail/ray_table.h"

namespace skypol::camera {
namespace {

// The distortion of the fisheye point p = (a, b) and its Jacobian, COLMAP's Distortion() plus p.
detail::Distorted distort(const std::array<double, 8>& c, const Eigen::Vector2d& p) {
  const auto [k1, k2, p1, p2, k3, k4, sx1, sy1] = c;
  const double a = p.x(), b = p.y();
  const double r2 = a * a + b * b;
  const double radial = r2 * (k1 + r2 * (k2 + r2 * (k3 + r2 * k4)));
  const double dradial = k1 + r2 * (2 * k2 + r2 * (3 * k3 + r2 * 4 * k4));  // dR/d(r²)
  detail::Distorted d;
  d.q = {a + a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a) + sx1 * r2,
         b + b * radial + 2 * p2 * a * b + p1 * (r2 + 2 * b * b) + sy1 * r2};
  d.jacobian << 1 + radial + 2 * a * a * dradial + 2 * p1 * b + 6 * p2 * a + 2 * sx1 * a,
      2 * a * b * dradial + 2 * p1 * a + 2 * p2 * b + 2 * sx1 * b,
      2 * a * b * dradial + 2 * p2 * b + 2 * p1 * a + 2 * sy1 * a,
      1 + radial + 2 * b * b * dradial + 2 * p2 * a + 6 * p1 * b + 2 * sy1 * b;
  return d;
}

}  // namespace

ThinPrismFisheyeLens::ThinPrismFisheyeLens(Intrinsics intrinsics, std::array<double, 8> coefficients,
                                           double max_field_angle)
    : k_(intrinsics), c_(coefficients), theta_max_(max_field_angle) {
  detail::check_intrinsics(k_);
  for (double v : c_)
    if (!std::isfinite(v)) throw std::invalid_argument("coefficients must be finite");
  if (!(std::isfinite(theta_max_) && theta_max_ > 0 && theta_max_ <= std::numbers::pi))
    throw std::invalid_argument("field of view must be in (0, 360]");
  if (const auto fold = detail::first_fold([this](const Eigen::Vector2d& p) { return distort(c_, p); }, theta_max_))
    throw std::invalid_argument("thin prism distortion not one-to-one over the declared field of view (folds at " +
                                detail::format_deg(*fold) + ")");
  // The radial part ρ·(1 + R(ρ²)) alone, inverted by a table, starts ray_row's Newton steps.
  table_ = std::make_shared<const detail::LazyRadialTable>([c = c_, t = theta_max_] {
    return detail::odd_polynomial_table({c[0], c[1], c[4], c[5]}, t);
  });
}

void ThinPrismFisheyeLens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                                   unsigned char* valid) const {
  const detail::RadialTable* table = table_->get();
  if (!table) return Lens::ray_row(y, x0, n, dx, dy, dz, valid);
  const auto [k1, k2, p1, p2, k3, k4, sx1, sy1] = c_;
  const Intrinsics k = k_;
  const auto norm = [k](double u, double v, double& mx, double& my) { mx = (u - k.cx) / k.fx, my = (v - k.cy) / k.fy; };
  // distort() of the anonymous namespace, its Eigen types spelled out as scalars.
  const auto dist = [=](double a, double b, double& qa, double& qb, double* j) {
    const double r2 = a * a + b * b;
    const double radial = r2 * (k1 + r2 * (k2 + r2 * (k3 + r2 * k4)));
    const double dradial = k1 + r2 * (2 * k2 + r2 * (3 * k3 + r2 * 4 * k4));
    qa = a + a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a) + sx1 * r2;
    qb = b + b * radial + 2 * p2 * a * b + p1 * (r2 + 2 * b * b) + sy1 * r2;
    j[0] = 1 + radial + 2 * a * a * dradial + 2 * p1 * b + 6 * p2 * a + 2 * sx1 * a;
    j[1] = 2 * a * b * dradial + 2 * p1 * a + 2 * p2 * b + 2 * sx1 * b;
    j[2] = 2 * a * b * dradial + 2 * p2 * b + 2 * p1 * a + 2 * sy1 * a;
    j[3] = 1 + radial + 2 * b * b * dradial + 2 * p2 * a + 6 * p1 * b + 2 * sy1 * b;
  };
  const detail::SinCosTable& sc = detail::sincos_table();
  const double tm = theta_max_;
  const auto lift = [&sc, tm](double a, double b, double pr, double& ox, double& oy, double& oz) {
    double s, c;
    detail::sincos_0_pi(sc, detail::vmin(pr, tm), s, c);
    const double s_r = s / detail::vmax(pr, 1e-300);
    ox = s_r * a, oy = s_r * b, oz = c;
    return true;
  };
  detail::undistort_ray_row(*table, theta_max_, norm, dist, lift, [this](const Eigen::Vector2d& p) { return ray(p); },
                            y, x0, n, dx, dy, dz, valid);
}

std::optional<Eigen::Vector2d> ThinPrismFisheyeLens::project(const Eigen::Vector3d& dir_cam) const {
  const auto p = detail::polar_of(dir_cam);
  if (!p || p->theta > theta_max_ + detail::kEdgeTol) return std::nullopt;
  const double t = std::min(p->theta, theta_max_);
  const Eigen::Vector2d q = distort(c_, {t * p->c, t * p->s}).q;
  return Eigen::Vector2d(k_.cx + k_.fx * q.x(), k_.cy + k_.fy * q.y());
}

std::optional<Eigen::Vector2d> ThinPrismFisheyeLens::undistort(const Eigen::Vector2d& m, double theta_limit) const {
  const auto p = detail::undistort_2d([this](const Eigen::Vector2d& x) { return distort(c_, x); }, m, m);
  if (!p || p->norm() > theta_limit * (1 + detail::kEdgeTol)) return std::nullopt;
  return p;
}

std::optional<Eigen::Vector3d> ThinPrismFisheyeLens::ray(const Eigen::Vector2d& pixel) const {
  if (!pixel.allFinite()) return std::nullopt;
  const Eigen::Vector2d m((pixel.x() - k_.cx) / k_.fx, (pixel.y() - k_.cy) / k_.fy);
  const auto p = undistort(m, theta_max_);
  if (!p) return std::nullopt;
  const double theta = std::min(p->norm(), theta_max_);
  return detail::direction(theta, p->x(), p->y(), p->norm());
}

std::shared_ptr<const Lens> ThinPrismFisheyeLens::rescaled(double s) const {
  return std::make_shared<ThinPrismFisheyeLens>(detail::rescale_intrinsics(k_, s), c_, theta_max_);
}

std::vector<std::pair<std::string, double>> ThinPrismFisheyeLens::parameters() const {
  auto p = Lens::parameters();
  const char* names[] = {"k1", "k2", "p1", "p2", "k3", "k4", "sx1", "sy1"};
  for (std::size_t i = 0; i < c_.size(); ++i) p.emplace_back(names[i], c_[i]);
  return p;
}

LensModel thin_prism_fisheye_lens_model() {
  LensModel m;
  m.name = "thin_prism_fisheye";
  m.description = "COLMAP's THIN_PRISM_FISHEYE (k1 k2 p1 p2 k3 k4 sx1 sy1)";
  m.fields = {LensField::coefficients};
  m.make = [](const LensSpec& s) -> std::shared_ptr<const Lens> {
    detail::need_coefficients(s, 8, "k1 k2 p1 p2 k3 k4 sx1 sy1");
    std::array<double, 8> c{};
    std::copy(s.coefficients.begin(), s.coefficients.end(), c.begin());
    return std::make_shared<ThinPrismFisheyeLens>(detail::pinhole_intrinsics(s), c, detail::half_fov(s, true));
  };
  return m;
}

}  // namespace skypol::camera
