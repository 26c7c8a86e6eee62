// Hand-made estimates for the tests that check arithmetic on poles (uncertainty, auto's ranking):
// a valid north pole at a level-frame azimuth and altitude, nothing else set.
#pragma once

#include <cmath>
#include <numbers>

#include "sky/units.h"
#include "skypole/estimate.h"

namespace skypol::testing {

inline skypole::PoleEstimate pole_at(double azimuth_deg, double altitude_deg) {
  skypole::PoleEstimate e;
  e.valid = true;
  e.is_north = true;
  e.altitude_deg = altitude_deg;
  e.azimuth_rel_deg = azimuth_deg;
  const double a = azimuth_deg * kRadPerDeg, h = altitude_deg * kRadPerDeg;
  e.pole_level = Eigen::Vector3d(std::cos(h) * std::sin(a), std::cos(h) * std::cos(a), std::sin(h));
  e.pole_camera = e.pole_level;
  return e;
}

}  // namespace skypol::testing
