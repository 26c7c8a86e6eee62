// Stokes identities: the frame rotation (Collett ch. 5 / Mitsuba 3's test) and Malus' law.
#include <catch2/catch.hpp>

#include <cmath>

#include "sky/stokes.h"
#include "sky_test_util.h"

using skypol::sky::from_polarization;
using skypol::sky::rotate_reference;
using skypol::sky::Stokes;
using namespace skypol::testing;

namespace {
// Radiance behind an ideal linear polarizer at angle theta from e0 towards e90.
double through_polarizer(const Stokes& s, double theta) {
  return 0.5 * (s.s0 + s.s1 * std::cos(2 * theta) + s.s2 * std::sin(2 * theta));
}
}  // namespace

TEST_CASE("rotating the basis of [1,1,0,0] by 45 degrees gives [1,0,-1,0]", "[stokes]") {
  const Stokes r = rotate_reference({1, 1, 0, 0}, 45 * kRadPerDeg);
  CHECK(r.s0 == 1.0);
  CHECK(r.s1 == Approx(0.0).margin(1e-15));
  CHECK(r.s2 == Approx(-1.0).margin(1e-15));
  CHECK(r.s3 == 0.0);
}

TEST_CASE("a basis rotation keeps S0, S3 and DoLP and lowers AoLP by the angle", "[stokes]") {
  const Stokes s{2.0, 0.3, -0.5, 0.1};
  for (double a : {-170.0, -45.0, 10.0, 90.0, 180.0, 333.0}) {
    const Stokes r = rotate_reference(s, a * kRadPerDeg);
    CHECK(r.s0 == s.s0);
    CHECK(r.s3 == s.s3);
    CHECK(r.dolp() == Approx(s.dolp()).epsilon(1e-14));
    CHECK(axial_diff(r.aolp(), s.aolp() - a * kRadPerDeg) == Approx(0.0).margin(1e-13));
  }
  const Stokes back = rotate_reference(rotate_reference(s, 0.7), -0.7);
  CHECK(back.s1 == Approx(s.s1).margin(1e-15));
  CHECK(back.s2 == Approx(s.s2).margin(1e-15));
  const Stokes half_turn = rotate_reference(s, kPi);  // a basis turned by 180° is the same basis
  CHECK(half_turn.s1 == Approx(s.s1).margin(1e-15));
  CHECK(half_turn.s2 == Approx(s.s2).margin(1e-15));
}

TEST_CASE("Malus' law: fully polarized light through a polarizer gives S0 cos^2", "[stokes]") {
  for (double psi : {-80.0, -30.0, 0.0, 22.5, 89.0}) {
    const Stokes s = from_polarization(3.0, 1.0, psi * kRadPerDeg);
    for (double theta = -90; theta <= 90; theta += 7.5) {
      const double c = std::cos((theta - psi) * kRadPerDeg);
      CHECK(through_polarizer(s, theta * kRadPerDeg) == Approx(3.0 * c * c).margin(1e-12));
    }
  }
  // Partially polarized: max/min behind the polarizer give DoLP = (Imax − Imin)/(Imax + Imin).
  const Stokes s = from_polarization(1.0, 0.4, 30 * kRadPerDeg);
  const double imax = through_polarizer(s, 30 * kRadPerDeg);
  const double imin = through_polarizer(s, 120 * kRadPerDeg);
  CHECK((imax - imin) / (imax + imin) == Approx(0.4).epsilon(1e-14));
}

TEST_CASE("DoLP and AoLP round trip and follow the documented rules", "[stokes]") {
  for (double psi : {-89.0, -45.0, 0.0, 45.0, 60.0, 90.0}) {
    const Stokes s = from_polarization(2.0, 0.6, psi * kRadPerDeg);
    CHECK(s.dolp() == Approx(0.6).epsilon(1e-14));
    CHECK(axial_diff(s.aolp(), psi * kRadPerDeg) == Approx(0.0).margin(1e-14));
    CHECK(s.aolp() > -kPi / 2);
    CHECK(s.aolp() <= kPi / 2);
  }
  CHECK(Stokes{1, -1, 0, 0}.aolp() == Approx(kPi / 2));   // E along e90: +90°, never −90°
  CHECK(Stokes{1, -1, -0.0, 0}.aolp() == Approx(kPi / 2));
  CHECK(Stokes{0, 0, 0, 0}.dolp() == 0.0);               // no light, no polarization
  CHECK(Stokes{1, 0, 0, 0}.aolp() == 0.0);               // undefined AoLP reported as 0
}
