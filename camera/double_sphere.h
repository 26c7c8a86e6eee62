// Double sphere camera model (Usenko, Demmel, Cremers, "The Double Sphere Camera Model",
// 3DV 2018, eqs. 40–47), closed form both ways.
// Parameter order (as in the paper and basalt): fx, fy, cx, cy, ξ (xi), α (alpha).
//   d1 = |p|,  d2 = |(x, y, ξ·d1 + z)|,  pixel = (cx, cy) + (fx·x, fy·y) / (α·d2 + (1−α)(ξ·d1 + z))
// It images directions with z > −w2·d1 (eq. 45), i.e. θ < acos(−w2); the declared field of view
// must lie inside, and ray() answers only inside the image circle of θmax.
#pragma once

#include "camera/lens.h"

namespace skypol::camera {

class DoubleSphereLens final : public Lens {
 public:
  // Throws std::invalid_argument: bad intrinsics, α ∉ [0, 1], ξ ∉ (−1, ∞) (not finite), or θmax
  // beyond the model's valid angle ("... exceeds the double sphere model's limit of 121.9°").
  DoubleSphereLens(Intrinsics intrinsics, double xi, double alpha, double max_field_angle);

  std::string name() const override { return "double_sphere"; }
  const Intrinsics& intrinsics() const override { return k_; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_cam) const override;
  std::optional<Eigen::Vector3d> ray(const Eigen::Vector2d& pixel) const override;
  // The closed form of ray() in one branch-free loop: the same bits as ray().
  void ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
               unsigned char* valid) const override;
  double max_field_angle() const override { return theta_max_; }
  std::shared_ptr<const Lens> rescaled(double s) const override;
  std::vector<std::pair<std::string, double>> parameters() const override;

  double xi() const { return xi_; }
  double alpha() const { return alpha_; }
  // The largest angle off the axis the model can image for (ξ, α): acos(−w2) (eq. 45).
  static double valid_angle(double xi, double alpha);
  // Normalized image radius of a direction θ off the axis.
  double radius(double theta) const;

 private:
  Intrinsics k_;
  double xi_, alpha_, theta_max_, r_max_;
};

}  // namespace skypol::camera
