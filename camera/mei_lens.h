// Mei's unified omnidirectional model with radial-tangential distortion, as OpenCV's cv::omnidir
// and Kalibr's omni-radtan (C. Mei & P. Rives, "Single View Point Omnidirectional Camera
// Calibration from Planar Grids", ICRA 2007). Images past 180° when ξ > 0.
// Parameter order (cv::omnidir): fx, fy, cx, cy, s (skew, K(0,1)), ξ (xi), k1, k2, p1, p2.
//   Xs = X/|X|;  (x, y) = (Xs.x, Xs.y)/(Xs.z + ξ)
//   r² = x² + y²,  x' = x·(1 + k1·r² + k2·r⁴) + 2·p1·x·y + p2·(r² + 2x²)
//                  y' = y·(1 + k1·r² + k2·r⁴) + p1·(r² + 2y²) + 2·p2·x·y
//   pixel = (fx·x' + s·y' + cx, fy·y' + cy)
// The model is one-to-one for Xs.z > −min(ξ, 1/ξ), i.e. θ < acos(−min(ξ, 1/ξ)); the declared field
// of view must lie inside and the distortion must not fold over it. The inverse undistorts by
// damped 2-D Newton, then lifts to the sphere in closed form (Mei & Rives eq. 5).
#pragma once

#include <array>
#include <memory>

#include "camera/lens.h"

namespace skypol::camera {
namespace detail {
class LazyRadialTable;
}

class MeiLens final : public Lens {
 public:
  // distortion = k1, k2, p1, p2. Throws std::invalid_argument for non-physical intrinsics, ξ < 0
  // or not finite, θmax beyond the model's limit, or a distortion that folds inside θmax.
  MeiLens(Intrinsics intrinsics, double skew, double xi, std::array<double, 4> distortion,
          double max_field_angle);

  std::string name() const override { return "mei"; }
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

  double xi() const { return xi_; }
  double skew() const { return skew_; }
  const std::array<double, 4>& distortion() const { return dist_; }
  // The largest angle off the axis the unified model images one-to-one for ξ.
  static double valid_angle(double xi);
  // Undistorted normalized radius of a direction θ off the axis: sin θ/(cos θ + ξ).
  double radius(double theta) const;

 private:
  Intrinsics k_;
  double skew_, xi_;
  std::array<double, 4> dist_;
  double theta_max_, r_max_;
  std::shared_ptr<const detail::LazyRadialTable> table_;  // the radial part's inverse, for ray_row
};

}  // namespace skypol::camera
