// Internal helpers shared by the rotationally symmetric lens models: polar decomposition of a
// direction, the edge of the field of view both ways (direction → pixel, pixel → normalized
// coordinates), intrinsics checks, the turning point of a radial curve and a bracketed solver.
// Not part of the camera interface.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "camera/detail/ray_kernels.h"
#include "camera/lens.h"

namespace skypol::camera::detail {

// Slack for directions and radii exactly on the edge of the field of view after a round trip.
inline constexpr double kEdgeTol = 1e-12;

// Angle θ off the optical axis and the azimuth (cos φ, sin φ) about it of a camera direction;
// nullopt for a zero, non-finite or straight-back direction (on the axis φ = 0).
struct Polar {
  double theta, c, s;
};
std::optional<Polar> polar_of(const Eigen::Vector3d& dir_cam);

// Unit direction at angle θ off the axis, azimuth along (mx, my)/r (r = |(mx, my)|, may be 0).
Eigen::Vector3d direction(double theta, double mx, double my, double r);

// Pixel at normalized radius r along the azimuth of p.
inline Eigen::Vector2d pixel_at(const Intrinsics& k, double r, const Polar& p) {
  return {k.cx + k.fx * r * p.c, k.cy + k.fy * r * p.s};
}

// The pixel of a camera direction on a lens whose normalized image height r(θ) rises up to θmax:
// nullopt beyond θmax; a direction within kEdgeTol past it (a round trip's rounding) lands on the
// edge.
template <class R>
std::optional<Eigen::Vector2d> project_radial(const Intrinsics& k, double theta_max, const Eigen::Vector3d& dir_cam,
                                              R r_of_theta) {
  const auto p = polar_of(dir_cam);
  if (!p || p->theta > theta_max + kEdgeTol) return std::nullopt;
  return pixel_at(k, r_of_theta(std::min(p->theta, theta_max)), *p);
}

// A pixel in normalized image coordinates m = ((u − cx)/fx, (v − cy)/fy), and r = |m|.
struct Normalized {
  double mx, my, r;
};

// The normalized coordinates of a pixel inside the image circle of normalized radius r_max (with
// kEdgeTol slack); nullopt for a non-finite pixel or one outside.
inline std::optional<Normalized> normalized_within(const Intrinsics& k, const Eigen::Vector2d& pixel, double r_max) {
  if (!pixel.allFinite()) return std::nullopt;
  const double mx = (pixel.x() - k.cx) / k.fx;
  const double my = (pixel.y() - k.cy) / k.fy;
  const double r = std::sqrt(mx * mx + my * my);  // not hypot: the row loops' arithmetic (ray_kernels.h)
  if (r > r_max * (1 + kEdgeTol)) return std::nullopt;
  return Normalized{mx, my, r};
}

// Lens::ray_row for a radial model whose ray(p) is direction(theta_of(r), m) inside the image
// circle of normalized radius r_max (normalized_within): the same arithmetic, so the same bits, in
// blocks of vector loops (detail/ray_kernels.h); theta_of is inlined, and called only inside.
template <class T>
void radial_ray_row(const Intrinsics& k, double r_max, T theta_of, double y, double x0, std::size_t n,
                    double* dx, double* dy, double* dz, unsigned char* valid) {
  const double my = (y - k.cy) / k.fy;
  const double limit = r_max * (1 + kEdgeTol);
  const bool finite = std::isfinite(y) && std::isfinite(x0) && std::isfinite(x0 + static_cast<double>(n));
  constexpr std::size_t kBlock = 256;
  double mx[kBlock], r[kBlock], theta[kBlock];
  for (std::size_t b = 0; b < n; b += kBlock) {
    const std::size_t m = std::min(kBlock, n - b);
    row_radii(x0, b, k.cx, k.fx, my, m, mx, r);
    // The pixels inside the circle are one span of the row (r is convex along it).
    std::size_t lo = m, hi = m;
    if (finite) valid_span(m, [&](std::size_t i) { return r[i] <= limit; }, lo, hi);
    for (std::size_t i = lo; i < hi; ++i) theta[i] = r[i] <= limit && r[i] > 0 ? theta_of(r[i]) : 0.0;
    radial_directions(m, lo, hi, my, limit, mx, r, theta, dx + b, dy + b, dz + b, valid + b);
  }
}

// Throws std::invalid_argument naming the key (fx, fy, cx, cy, width, height).
void check_intrinsics(const Intrinsics& k);

// Intrinsics of the same lens on a grid u' = s·(u + ½) − ½.
Intrinsics rescale_intrinsics(const Intrinsics& k, double s);

// The smallest θ in (0, θmax] where the derivative dr(θ) of a radial curve stops being positive
// (a dense scan, then bisection), or nullopt if the curve rises over the whole range.
template <class DR>
std::optional<double> first_turning_point(DR dr, double theta_max, int samples = 8192) {
  double prev = 0;
  for (int i = 1; i <= samples; ++i) {
    const double t = theta_max * i / samples;
    if (!(dr(t) > 0)) {
      double lo = prev, hi = t;
      for (int j = 0; j < 200 && hi - lo > 1e-15; ++j) {
        const double mid = 0.5 * (lo + hi);
        (dr(mid) > 0 ? lo : hi) = mid;
      }
      return lo;
    }
    prev = t;
  }
  return std::nullopt;
}

// Solves f(x) = target for x in [lo, hi], f non-decreasing there with f(lo) ≤ target ≤ f(hi):
// Newton steps from `guess`, replaced by bisection whenever they leave the bracket, so it always
// converges (to the bracket's resolution where f' vanishes). nullopt only if the bracket does
// not hold the target or the iteration budget runs out.
template <class F, class DF>
std::optional<double> solve_increasing(F f, DF df, double target, double lo, double hi,
                                       double guess) {
  if (!(f(lo) <= target) || !(f(hi) >= target)) return std::nullopt;
  double x = std::clamp(guess, lo, hi);
  for (int i = 0; i < 200; ++i) {
    const double fx = f(x) - target;
    if (fx == 0) return x;
    (fx > 0 ? hi : lo) = x;
    const double d = df(x);
    double xn = x - fx / d;
    if (!(d > 0) || !(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
    if (std::abs(xn - x) <= 1e-15 * std::max(1.0, std::abs(x))) return xn;
    if (hi - lo <= 1e-15 * std::max(1.0, std::abs(hi))) return xn;
    x = xn;
  }
  return std::nullopt;
}

std::string format_deg(double rad);  // "87.3°"

}  // namespace skypol::camera::detail
