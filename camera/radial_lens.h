// The five ideal radial mappings of Sun et al. 2019 eq. 7, r = image height in focal-length units:
//   perspective     r = tan θ          stereographic  r = 2 tan(θ/2)
//   equidistant     r = θ              equisolid      r = 2 sin(θ/2)
//   orthographic    r = sin θ   ("vertical projection" in Sun et al.)
// pixel = (cx + fx·r·cos φ, cy + fy·r·sin φ), φ the direction's azimuth about the optical axis.
// Parameters: fx, fy, cx, cy (Intrinsics), and the maximum field angle θmax (half the FOV).
#pragma once

#include <string_view>

#include "camera/lens.h"

namespace skypol::camera {

enum class Mapping { perspective, stereographic, equidistant, equisolid, orthographic };

// "equidistant" → Mapping::equidistant; throws std::invalid_argument listing the legal names.
Mapping parse_mapping(std::string_view name);
std::string_view mapping_name(Mapping m);

class RadialLens final : public Lens {
 public:
  // Throws std::invalid_argument for non-physical parameters (fx, fy ≤ 0, θmax beyond what the
  // mapping can image: perspective < 90°, orthographic ≤ 90°, stereographic < 180°).
  RadialLens(Mapping mapping, Intrinsics intrinsics, double max_field_angle);

  std::string name() const override;
  const Intrinsics& intrinsics() const override { return k_; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_cam) const override;
  std::optional<Eigen::Vector3d> ray(const Eigen::Vector2d& pixel) const override;
  void ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
               unsigned char* valid) const override;
  double max_field_angle() const override { return theta_max_; }
  std::shared_ptr<const Lens> rescaled(double s) const override;
  Mapping mapping() const { return mapping_; }

  // r(θ) and θ(r) of the mapping, in focal-length units.
  double radius(double theta) const;
  double angle(double radius) const;

 private:
  Mapping mapping_;
  Intrinsics k_;
  double theta_max_;
};

}  // namespace skypol::camera
