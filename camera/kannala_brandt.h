// Kannala–Brandt fisheye model with four coefficients, as OpenCV's cv::fisheye and COLMAP's
// OPENCV_FISHEYE (Kannala & Brandt, IEEE TPAMI 28(8), 2006, eq. 6 truncated to k1..k4).
// Parameter order (OpenCV / COLMAP): fx, fy, cx, cy, k1, k2, k3, k4.
//   θ  = atan2(√(x² + y²), z)  (OpenCV uses atan(r/z); atan2 keeps it valid past 90°)
//   θd = θ·(1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸)
//   pixel = (cx + fx·θd·cos φ, cy + fy·θd·sin φ)
// ray() solves θd(θ) = r by bracketed Newton; ray_row interpolates a table of it (ray_table.h). A polynomial that turns over (dθd/dθ ≤ 0)
// inside the declared field of view is rejected, or the field of view is cut at the turning
// point when asked (then pixels beyond it are masked).
#pragma once

#include <array>
#include <memory>

#include "camera/lens.h"

namespace skypol::camera {
namespace detail {
class LazyRadialTable;
}

class KannalaBrandtLens final : public Lens {
 public:
  enum class OnTurnover { reject, clamp_fov };

  // Throws std::invalid_argument for non-physical intrinsics, a non-finite coefficient, θmax not
  // in (0, π], or (OnTurnover::reject) a curve that turns over at or before θmax: "distortion
  // curve not monotone over the declared field of view (turns over at 87.3°)".
  KannalaBrandtLens(Intrinsics intrinsics, std::array<double, 4> k, double max_field_angle,
                    OnTurnover on_turnover = OnTurnover::reject);

  std::string name() const override { return "kannala_brandt"; }
  const Intrinsics& intrinsics() const override { return k_; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_cam) const override;
  std::optional<Eigen::Vector3d> ray(const Eigen::Vector2d& pixel) const override;
  // θ(r) from a table built once (detail/ray_table.h) and one Newton step: ray() to ~1e-15 rad,
  // not bit for bit; pixels at the circle's edge or near a turning point take ray() itself.
  void ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
               unsigned char* valid) const override;
  double max_field_angle() const override { return theta_max_; }
  std::shared_ptr<const Lens> rescaled(double s) const override;
  std::vector<std::pair<std::string, double>> parameters() const override;

  const std::array<double, 4>& coefficients() const { return coef_; }
  // θd(θ) and its derivative, focal-length units.
  double distorted(double theta) const;
  double distorted_derivative(double theta) const;

 private:
  Intrinsics k_;
  std::array<double, 4> coef_;
  double theta_max_;
  double r_max_;  // θd(θmax)
  std::shared_ptr<const detail::LazyRadialTable> table_;  // θ(θd), for ray_row
};

}  // namespace skypol::camera
