// Extended unified camera model, EUCM (Khomutenko, Garcia, Martinet, "An Enhanced Unified Camera
// Model", IEEE RA-L 1(1), 2016; as in Kalibr/basalt "eucm"), closed form both ways.
// Parameter order (basalt, Kalibr): fx, fy, cx, cy, α (alpha), β (beta).
//   d = √(β·(x² + y²) + z²),  pixel = (cx, cy) + (fx·x, fy·y)/(α·d + (1 − α)·z)
//   inverse: r² = mx² + my²,  mz = (1 − β·α²·r²)/(α·√(1 − (2α − 1)·β·r²) + 1 − α),  ray ∝ (mx, my, mz)
// β = 1 is Mei's model without distortion with ξ = α/(1 − α) and f scaled by 1/(1 − α).
// The declared field of view must lie where the image radius rises with θ (checked).
#pragma once

#include "camera/lens.h"

namespace skypol::camera {

class EucmLens final : public Lens {
 public:
  // Throws std::invalid_argument: bad intrinsics, α ∉ [0, 1], β ≤ 0 (or not finite), or an image
  // radius that stops rising (or a denominator that reaches 0) before θmax.
  EucmLens(Intrinsics intrinsics, double alpha, double beta, double max_field_angle);

  std::string name() const override { return "eucm"; }
  const Intrinsics& intrinsics() const override { return k_; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_cam) const override;
  std::optional<Eigen::Vector3d> ray(const Eigen::Vector2d& pixel) const override;
  // The closed form of ray() in one branch-free loop: the same bits as ray().
  void ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
               unsigned char* valid) const override;
  double max_field_angle() const override { return theta_max_; }
  std::shared_ptr<const Lens> rescaled(double s) const override;
  std::vector<std::pair<std::string, double>> parameters() const override;

  double alpha() const { return alpha_; }
  double beta() const { return beta_; }
  // Normalized image radius of a direction θ off the axis.
  double radius(double theta) const;

 private:
  Intrinsics k_;
  double alpha_, beta_, theta_max_, r_max_;
};

}  // namespace skypol::camera
