// A lens given by its real image height curve, as lens makers publish it (field angle → image
// height), interpolated by a monotone cubic (Fritsch & Carlson, SIAM J. Numer. Anal. 17(2), 1980)
// so the curve never overshoots or turns over between table points; the inverse solves the cubic
// of the one segment that holds the radius (bracketed Newton), so round trips are exact.
// Parameters: fx, fy, cx, cy (Intrinsics; fx = pixels per table height unit) and the table
// (θ radians ascending, height ascending; (0, 0) is added when missing). θmax = last table angle.
#pragma once

#include <vector>

#include "camera/lens.h"

namespace skypol::camera {

struct HeightTable {
  std::vector<double> theta;   // field angle off the axis, radians, strictly ascending, ≥ 0
  std::vector<double> height;  // image height (any unit; pixels = height·fx), strictly ascending
};

// Converts a maker's table (field angle degrees, image height mm) to a HeightTable in mm.
HeightTable height_table_from_deg_mm(const std::vector<std::pair<double, double>>& deg_mm);

class TabulatedLens final : public Lens {
 public:
  // Throws std::invalid_argument: fewer than 2 points, sizes differ, a non-finite entry, angles or
  // heights not strictly ascending ("image height table not monotone at 80°"), θ > 180°, a
  // non-zero height at θ = 0.
  TabulatedLens(Intrinsics intrinsics, HeightTable table);

  std::string name() const override { return "tabulated"; }
  const Intrinsics& intrinsics() const override { return k_; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_cam) const override;
  std::optional<Eigen::Vector3d> ray(const Eigen::Vector2d& pixel) const override;
  void ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
               unsigned char* valid) const override;
  double max_field_angle() const override { return t_.theta.back(); }
  std::shared_ptr<const Lens> rescaled(double s) const override;
  std::vector<std::pair<std::string, double>> parameters() const override;

  // Interpolated height at θ (table units) and its inverse.
  double height(double theta) const;
  double angle(double height) const;

 private:
  std::size_t segment_of_theta(double theta) const;
  double hermite(std::size_t i, double theta) const;
  double hermite_derivative(std::size_t i, double theta) const;

  Intrinsics k_;
  HeightTable t_;
  std::vector<double> slope_;  // Fritsch–Carlson tangents at the table points
};

}  // namespace skypol::camera
