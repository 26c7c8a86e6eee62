// heading/tilt/roll and quaternions against the worked examples written in orientation.h.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/LU>

#include "camera/orientation.h"
#include "sky/units.h"

using namespace skypol::camera;
using skypol::kRadPerDeg;

namespace {
const Eigen::Vector3d kEast(1, 0, 0), kNorth(0, 1, 0), kUp(0, 0, 1);

void check_vec(const Eigen::Vector3d& got, const Eigen::Vector3d& want) {
  INFO("got " << got.transpose() << " want " << want.transpose());
  CHECK((got - want).norm() < 1e-12);
}
}  // namespace

TEST_CASE("heading 90°, tilt 0, roll 0: camera +x North, +y West, +z Up (orientation.h)", "[orientation]") {
  const Eigen::Matrix3d r = world_from_heading_tilt_roll(90, 0, 0);
  check_vec(r.col(0), kNorth);
  check_vec(r.col(1), -kEast);
  check_vec(r.col(2), kUp);
}

TEST_CASE("heading 0, tilt 90°, roll 180°: upright level camera looking North", "[orientation]") {
  const Eigen::Matrix3d r = world_from_heading_tilt_roll(0, 90, 180);
  check_vec(r.col(0), kEast);
  check_vec(r.col(1), -kUp);
  check_vec(r.col(2), kNorth);
  // Without the roll the level camera is upside down: image-up (−y) is Down.
  check_vec(-world_from_heading_tilt_roll(0, 90, 0).col(1), -kUp);
}

TEST_CASE("zenith camera, heading 0: image-up North, image-right West (mirrored sky)", "[orientation]") {
  const Eigen::Matrix3d r = world_from_heading_tilt_roll(0, 0, 0);
  check_vec(-r.col(1), kNorth);
  check_vec(r.col(0), -kEast);
  // Roll 30° turns image-up towards the former image-right (West): azimuth −30° = 330°.
  const Eigen::Matrix3d rr = world_from_heading_tilt_roll(0, 0, 30);
  check_vec(-rr.col(1), Eigen::Vector3d(-std::sin(30 * kRadPerDeg), std::cos(30 * kRadPerDeg), 0));
  CHECK(heading_deg_of(rr) == Approx(330));
}

TEST_CASE("tilt tips the optical axis towards the heading; image-up tips down", "[orientation]") {
  const double psi = 30 * kRadPerDeg, tau = 40 * kRadPerDeg;
  const Eigen::Matrix3d r = world_from_heading_tilt_roll(30, 40, 0);
  const Eigen::Vector3d h(std::sin(psi), std::cos(psi), 0);  // horizontal unit vector at azimuth ψ
  check_vec(r.col(2), std::sin(tau) * h + std::cos(tau) * kUp);  // elevation 50° at azimuth 30°
  check_vec(-r.col(1), std::cos(tau) * h - std::sin(tau) * kUp);
  CHECK(r.determinant() == Approx(1));
}

TEST_CASE("heading_deg_of inverts world_from_heading_tilt_roll", "[orientation]") {
  for (double psi : {0.0, 1e-7, 37.0, 90.0, 179.9, 180.0, 271.5, 359.999})
    for (double tau : {0.0, 0.5, 45.0, 90.0, 135.0, 180.0})
      for (double rho : {0.0, 25.0, -170.0}) {
        if ((tau == 0 || tau == 180) && rho != 0) continue;  // heading and roll degenerate there
        const double got = heading_deg_of(world_from_heading_tilt_roll(psi, tau, rho));
        INFO("psi " << psi << " tau " << tau << " rho " << rho << " got " << got);
        const double diff = std::remainder(got - psi, 360.0);
        CHECK(std::abs(diff) < 1e-9);
        CHECK(got >= 0);
        CHECK(got < 360);
      }
  // Negative and >360 headings wrap into [0, 360).
  CHECK(heading_deg_of(world_from_heading_tilt_roll(-90, 10, 0)) == Approx(270));
  CHECK(heading_deg_of(world_from_heading_tilt_roll(450, 10, 0)) == Approx(90));
}

TEST_CASE("quaternion (cos 45°, 0, 0, sin 45°) is the heading-90° zenith camera", "[orientation]") {
  const double c = std::cos(45 * kRadPerDeg);
  const Eigen::Matrix3d q = world_from_quaternion(c, 0, 0, c);
  CHECK((q - world_from_heading_tilt_roll(90, 0, 0)).cwiseAbs().maxCoeff() < 1e-12);
  // Normalised on input.
  CHECK((world_from_quaternion(2 * c, 0, 0, 2 * c) - q).cwiseAbs().maxCoeff() < 1e-12);
}

TEST_CASE("bad orientations are rejected", "[orientation]") {
  CHECK_THROWS_WITH(world_from_heading_tilt_roll(0, -1, 0), Catch::Contains("tilt_deg"));
  CHECK_THROWS_WITH(world_from_heading_tilt_roll(0, 180.5, 0), Catch::Contains("tilt_deg"));
  CHECK_THROWS_WITH(world_from_heading_tilt_roll(NAN, 0, 0), Catch::Contains("heading_deg"));
  CHECK_THROWS_WITH(world_from_heading_tilt_roll(0, 0, INFINITY), Catch::Contains("roll_deg"));
  CHECK_THROWS_AS(world_from_quaternion(0, 0, 0, 0), std::invalid_argument);
  CHECK_THROWS_AS(world_from_quaternion(1, NAN, 0, 0), std::invalid_argument);
}
