// Angle units: π, the degree and the radian, the one place the tree defines them. Degrees at every
// interface a person sees, radians inside (docs/conventions.md). Each name says which way it
// converts: kRadPerDeg is one degree in radians (x_deg * kRadPerDeg is radians, x_rad / kRadPerDeg
// is degrees), kDegPerRad is one radian in degrees (x_rad * kDegPerRad is degrees).
// In namespace skypol rather than skypol::sky: every room uses them, and code in any skypol::room
// namespace reads them unqualified.
#pragma once

#include <numbers>

namespace skypol {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kRadPerDeg = std::numbers::pi / 180;  // one degree in radians
inline constexpr double kDegPerRad = 180 / std::numbers::pi;  // one radian in degrees

// x·π/180 and x·180/π evaluated left to right, (x·π)/180 and (x·180)/π. Multiplying by the
// rounded constant instead (x * kRadPerDeg) can differ in the last bit, so code that multiplies
// by the constant keeps the constant and code that writes the product and quotient calls these.
constexpr double rad_from_deg(double deg) { return deg * std::numbers::pi / 180; }
constexpr double deg_from_rad(double rad) { return rad * 180 / std::numbers::pi; }

}  // namespace skypol
