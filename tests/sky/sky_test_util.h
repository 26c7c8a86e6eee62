// What the sky tests share: a sun placed by hand, a basis vector for a view direction when the
// test does not care which, random directions, and the batch path run beside the scalar one.
#pragma once

#include <cmath>
#include <cstddef>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "sky/sky_model.h"
#include "sky/stokes.h"
#include "sky/sun.h"
#include "sky/units.h"

namespace skypol::testing {

using skypol::kPi;
using skypol::kRadPerDeg;

// A sun at an azimuth (from North towards East) and an elevation in degrees, without a site or a
// time: the sky models read only these and the direction.
inline sky::Sun sun_at(double azimuth_deg, double elevation_deg) {
  sky::Sun s;
  s.azimuth = azimuth_deg * kRadPerDeg;
  s.elevation = elevation_deg * kRadPerDeg;
  s.direction = sky::enu_direction(s.azimuth, s.elevation);
  return s;
}

// A unit vector ⟂ d, for an e0 whose choice the check does not depend on (DoLP, radiance, or
// a comparison of two paths given the same basis).
inline Eigen::Vector3d perpendicular(const Eigen::Vector3d& d) {
  const Eigen::Vector3d a = std::abs(d.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  return (a - a.dot(d) * d).normalized();
}

// A direction uniform on the sphere. A fresh distribution per call, so a test's sequence depends
// only on its seed and the number of calls.
inline Eigen::Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}

// A unit vector ⟂ d in a random direction (one random_unit draw, made ⟂ d): any basis, not only
// a meridian one.
inline Eigen::Vector3d random_perpendicular(const Eigen::Vector3d& d, std::mt19937_64& rng) {
  const Eigen::Vector3d e = random_unit(rng);
  return (e - e.dot(d) * d).normalized();
}

// Difference of two axial angles (period π), in (−π/2, π/2].
inline double axial_diff(double a, double b) { return std::remainder(a - b, kPi); }

// One ray's Stokes from the batch path (float, vectorized) and from the scalar path (double).
struct BatchAndScalar {
  sky::StokesF batch;
  sky::Stokes scalar;
};

// Both paths of `sky` over the same rays, for the tests that hold the batch path to the scalar
// one with the tolerance their model's float approximations allow.
inline std::vector<BatchAndScalar> batch_and_scalar(const sky::SkyModel& sky, std::span<const sky::ViewRay> rays,
                                                    const sky::Sun& sun) {
  std::vector<sky::StokesF> out(rays.size());
  sky.stokes(rays, sun, out);
  std::vector<BatchAndScalar> both;
  both.reserve(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
    both.push_back({out[i], sky.stokes(rays[i].d.cast<double>(), rays[i].e0.cast<double>(), sun)});
  return both;
}

}  // namespace skypol::testing
