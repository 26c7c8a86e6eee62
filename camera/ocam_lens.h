// Scaramuzza's omnidirectional model as calibrated by the OCamCalib toolbox (Scaramuzza,
// Martinelli, Siegwart, ICVS 2006; Rufli et al. IROS 2008), read from its calib_results.txt.
// Parameters (OCamCalib names and order): pol a0..aN (cam2world: z = Σ ai·ρ^i), invpol (world2cam
// initial guess only), xc yc = image centre as ROW and COLUMN (0-based, C convention), affine
// c d e, image height and width.
//   OCamCalib frame: X along rows, Y along columns, Z = X × Y pointing back out of the lens (a0 < 0
//   for points in front). In skypol's camera frame that is d = (Y, X, −Z).
//   [row − xc; col − yc] = [c d; e 1]·[x'; y'],  ρ = |(x', y')|,  3-D ray ∝ (x', y', pol(ρ)).
// ray() is that closed form; project() solves θ(ρ) = atan2(ρ, −pol(ρ)) exactly (bracketed Newton
// started from invpol), so round trips are exact rather than invpol-accurate.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "camera/lens.h"

namespace skypol::camera {

struct OCamModel {
  std::vector<double> pol;     // a0, a1, ..., aN
  std::vector<double> invpol;  // p0, p1, ...: ρ = Σ pi·t^i, t = atan(Z/√(X²+Y²))
  double xc = 0, yc = 0;       // row, column of the centre (0-based)
  double c = 1, d = 0, e = 0;  // affine
  int height = 0, width = 0;
};

// Reads OCamCalib's calib_results.txt (comment lines start with '#'; the five data lines are
// "N a0 .. aN-1", "M p0 .. pM-1", "xc yc", "c d e", "height width"). Throws
// std::invalid_argument naming the file and the line that is missing or malformed.
OCamModel load_ocamcalib(const std::filesystem::path& path);
// The same from the file's text (a stack header carries it); `name` labels the messages.
OCamModel parse_ocamcalib(const std::string& text, const std::string& name);

class OCamLens final : public Lens {
 public:
  // max_field_angle ≤ 0 means: the angle at the farthest sensor corner, cut at the first turning
  // point of θ(ρ). Throws std::invalid_argument for an empty pol, a0 ≥ 0, a singular affine
  // (c − d·e = 0), a non-positive size, or a θ(ρ) that turns over before max_field_angle.
  OCamLens(OCamModel model, double max_field_angle = 0);

  std::string name() const override { return "ocam"; }
  // fx = fy = −a0 (pixels per unit of tan θ near the axis), cx = yc, cy = xc; informative only.
  const Intrinsics& intrinsics() const override { return k_; }
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_cam) const override;
  std::optional<Eigen::Vector3d> ray(const Eigen::Vector2d& pixel) const override;
  // The closed form of ray() in one branch-free loop: the same bits as ray().
  void ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
               unsigned char* valid) const override;
  double max_field_angle() const override { return theta_max_; }
  std::shared_ptr<const Lens> rescaled(double s) const override;
  std::vector<std::pair<std::string, double>> parameters() const override;

  const OCamModel& model() const { return m_; }
  // Angle off the axis of the ray at pre-affine radius ρ (pixels), and its derivative.
  double theta_of_rho(double rho) const;
  double dtheta_drho(double rho) const;

 private:
  double pol(double rho) const;
  double pol_derivative(double rho) const;

  OCamModel m_;
  Intrinsics k_;
  double theta_max_ = 0, rho_max_ = 0;
};

}  // namespace skypol::camera
