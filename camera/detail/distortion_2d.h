// Internal helpers for the lens models whose distortion is not rotationally symmetric (radial
// plus tangential / thin-prism terms on a 2-D point): the inverse by damped Newton, and the check
// that the map stays one-to-one (Jacobian determinant > 0) over a disc. Not part of the interface.
#pragma once

#include <cmath>
#include <optional>

#include <Eigen/Core>
#include <Eigen/LU>

#include "sky/units.h"

namespace skypol::camera::detail {

// A distortion map p ↦ q(p) with its Jacobian.
struct Distorted {
  Eigen::Vector2d q;
  Eigen::Matrix2d jacobian;
};

// Solves q(p) = target for p, starting at `start`: Newton steps, halved while they do not reduce
// the residual (so a strong distortion cannot throw the iterate away). Converges quadratically
// where det J > 0; stops at a residual of 1e-15 (relative). nullopt if it does not converge.
template <class Q>
std::optional<Eigen::Vector2d> undistort_2d(Q q_of, const Eigen::Vector2d& target, Eigen::Vector2d start) {
  Eigen::Vector2d p = start;
  Distorted d = q_of(p);
  double res = (d.q - target).norm();
  const double tol = 1e-15 * std::max(1.0, target.norm());
  for (int i = 0; i < 100 && res > tol; ++i) {
    const double det = d.jacobian.determinant();
    if (!(std::abs(det) > 0) || !std::isfinite(det)) return std::nullopt;
    const Eigen::Vector2d step = d.jacobian.inverse() * (target - d.q);
    double t = 1;
    bool moved = false;
    for (int h = 0; h < 40; ++h, t *= 0.5) {
      const Eigen::Vector2d pn = p + t * step;
      const Distorted dn = q_of(pn);
      const double rn = (dn.q - target).norm();
      if (std::isfinite(rn) && rn < res) {
        p = pn, d = dn, res = rn, moved = true;
        break;
      }
    }
    if (!moved) break;  // at the floor of double precision
  }
  if (!(res <= 1e-12 * std::max(1.0, target.norm())) || !p.allFinite()) return std::nullopt;
  return p;
}

// The smallest radius in (0, r_max] at which det J(q) ≤ 0 somewhere on the circle (sampled at
// 360 azimuths, 512 radii), or nullopt if the map keeps its orientation over the whole disc.
template <class Q>
std::optional<double> first_fold(Q q_of, double r_max) {
  constexpr int kRadii = 512, kAzimuths = 360;
  for (int i = 1; i <= kRadii; ++i) {
    const double r = r_max * i / kRadii;
    for (int j = 0; j < kAzimuths; ++j) {
      const double phi = 2 * kPi * j / kAzimuths;
      const double det = q_of(Eigen::Vector2d(r * std::cos(phi), r * std::sin(phi))).jacobian.determinant();
      if (!(det > 0)) return r;
    }
  }
  return std::nullopt;
}

}  // namespace skypol::camera::detail
