// COLMAP's THIN_PRISM_FISHEYE camera model (colmap/sensor/models.h, ThinPrismFisheyeCameraModel;
// Weng, Cohen & Herniou, IEEE TPAMI 14(10), 1992, for the tangential and thin-prism terms).
// Parameter order (COLMAP): fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1.
//   θ = atan2(√(x² + y²), z);  (a, b) = θ·(x, y)/√(x² + y²)   (equidistant "fisheye" point)
//   r² = a² + b²,  R = k1·r² + k2·r⁴ + k3·r⁶ + k4·r⁸
//   a' = a + a·R + 2·p1·a·b + p2·(r² + 2a²) + sx1·r²
//   b' = b + b·R + 2·p2·a·b + p1·(r² + 2b²) + sy1·r²
//   pixel = (cx + fx·a', cy + fy·b')   (skypol's pixel centres: COLMAP's cx, cy minus 0.5)
// COLMAP stops at z > 0; θ from atan2 carries the same formula past 90°. The inverse is a damped
// 2-D Newton solve; the distortion must stay one-to-one (det J > 0) over the declared field.
#pragma once

#include <array>
#include <memory>

#include "camera/lens.h"

namespace skypol::camera {
namespace detail {
class LazyRadialTable;
}

class ThinPrismFisheyeLens final : public Lens {
 public:
  // Throws std::invalid_argument for non-physical intrinsics, a non-finite coefficient, θmax not
  // in (0, π], or a distortion that folds inside θmax ("... not one-to-one ... (folds at 97.1°)").
  ThinPrismFisheyeLens(Intrinsics intrinsics, std::array<double, 8> coefficients, double max_field_angle);

  std::string name() const override { return "thin_prism_fisheye"; }
  const Intrinsics& intrinsics() const override { return k_; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_cam) const override;
  std::optional<Eigen::Vector3d> ray(const Eigen::Vector2d& pixel) const override;
  // Starts Newton from a table of the radial part's inverse (detail/ray_table.h), three steps
  // without branches: ray() to ~1e-15 rad, not bit for bit; the pixels the steps leave unsettled,
  // and those at the field's edge, take ray() itself. The base version where the radial part
  // alone turns over inside the field.
  void ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
               unsigned char* valid) const override;
  double max_field_angle() const override { return theta_max_; }
  std::shared_ptr<const Lens> rescaled(double s) const override;
  std::vector<std::pair<std::string, double>> parameters() const override;

  const std::array<double, 8>& coefficients() const { return c_; }
  // The fisheye point (a, b) of a normalized image point, or nullopt (no convergence, or beyond
  // θmax). Used by importers to find the angle of the sensor corners.
  std::optional<Eigen::Vector2d> undistort(const Eigen::Vector2d& normalized, double theta_limit) const;

 private:
  Intrinsics k_;
  std::array<double, 8> c_;
  double theta_max_;
  std::shared_ptr<const detail::LazyRadialTable> table_;  // the radial part's inverse, for ray_row
};

}  // namespace skypol::camera
