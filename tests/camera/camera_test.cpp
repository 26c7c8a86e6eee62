// Camera: rays in the world, the meridional basis, projected vs meridional transport, truth pixels.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <numbers>

#include "camera/camera.h"
#include "camera/orientation.h"
#include "camera/radial_lens.h"
#include "camera_test_util.h"
#include "sky/units.h"

using namespace skypol::camera;
using namespace skypol::testing;
using skypol::kPi, skypol::kRadPerDeg;

namespace {

std::shared_ptr<const Lens> fisheye185() {
  return std::make_shared<RadialLens>(Mapping::equidistant, imx250(), 92.5 * kRadPerDeg);
}

// The pixel that sees camera-frame direction (θ, φ) on the equidistant lens (by hand).
Eigen::Vector2d pixel_of(double theta, double phi) {
  return {1223.5 + kF * theta * std::cos(phi), 1023.5 + kF * theta * std::sin(phi)};
}
}  // namespace

TEST_CASE("meridional e0 matches cos φ·m − sin φ·s, is unit, ⟂ d, and +x on the axis", "[camera]") {
  CHECK((meridional_e0({0, 0, 1}) - Eigen::Vector3d::UnitX()).norm() < 1e-15);
  for (double theta : {1e-9, 0.3, 1.2, kPi / 2, 1.7, 3.0})
    for (double phi : {0.0, 0.7, 2.0, -2.5}) {
      const Eigen::Vector3d d = dir(theta, phi);
      const Eigen::Vector3d m(std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi),
                              -std::sin(theta));
      const Eigen::Vector3d s(-std::sin(phi), std::cos(phi), 0);
      const Eigen::Vector3d e0 = meridional_e0(d);
      INFO("theta " << theta << " phi " << phi);
      CHECK((e0 - (std::cos(phi) * m - std::sin(phi) * s)).norm() < 1e-12);
      CHECK(std::abs(e0.dot(d)) < 1e-14);
      CHECK(e0.norm() == Approx(1).epsilon(1e-15));
    }
  // Straight back: a defined unit vector, never NaN.
  CHECK(meridional_e0({0, 0, -1}).allFinite());
  CHECK(meridional_e0({1e-200, 0, -1}).allFinite());
}

TEST_CASE("camera ray at the principal point: d = optical axis, e0 = camera +x in the world", "[camera]") {
  const Eigen::Matrix3d r = world_from_heading_tilt_roll(90, 0, 0);  // +x North, +z Up
  Camera cam(fisheye185(), r);
  auto ray = cam.ray({1223.5, 1023.5});
  REQUIRE(ray);
  CHECK((ray->d - Eigen::Vector3d(0, 0, 1)).norm() < 1e-15);
  CHECK((ray->e0 - Eigen::Vector3d(0, 1, 0)).norm() < 1e-15);
  CHECK_FALSE(cam.ray({0, 0}));  // corner: outside the image circle
}

TEST_CASE("the north celestial pole lands where the heading says", "[camera]") {
  // Marseille (SkyPole): latitude 43.287°. NCP at azimuth 0, elevation = latitude; zenith angle
  // 46.713° → r = f·0.81530 = 425.37 px from the centre.
  const double lat = 43.286987 * kRadPerDeg;
  const Eigen::Vector3d ncp(0, std::cos(lat), std::sin(lat));
  const double r = kF * (kPi / 2 - lat);
  {  // heading 0: image-up North → NCP straight above the centre.
    Camera cam(fisheye185(), world_from_heading_tilt_roll(0, 0, 0));
    auto p = cam.project(ncp);
    REQUIRE(p);
    CHECK((*p - Eigen::Vector2d(1223.5, 1023.5 - r)).norm() < 1e-9);
  }
  {  // heading 90: camera +x is North → NCP to the right of the centre.
    Camera cam(fisheye185(), world_from_heading_tilt_roll(90, 0, 0));
    auto p = cam.project(ncp);
    REQUIRE(p);
    CHECK((*p - Eigen::Vector2d(1223.5 + r, 1023.5)).norm() < 1e-9);
    auto back = cam.ray(*p);
    REQUIRE(back);
    CHECK((back->d - ncp).norm() < 1e-12);
  }
}

TEST_CASE("projected transport differs from meridional far off-axis by hand-computed angles", "[camera]") {
  // Any orientation: the angles depend only on the camera-frame direction.
  for (const Eigen::Matrix3d& r :
       {Eigen::Matrix3d(Eigen::Matrix3d::Identity()), world_from_heading_tilt_roll(37, 20, -65)}) {
    Camera merid(fisheye185(), r, Transport::meridional);
    Camera proj(fisheye185(), r, Transport::projected);
    {
      // θ = 80°, φ = 45°: e0 in the camera frame is (1 − c²(1−cosθ), −cs(1−cosθ), −sinθ·c) with
      // c = s = 1/√2, whose sensor-plane angle is −atan(tan²(θ/2)) = −atan(tan²40°) = −35.149°.
      auto ray = proj.ray(pixel_of(80 * kRadPerDeg, 45 * kRadPerDeg));
      REQUIRE(ray);
      const double want = -std::atan(std::pow(std::tan(40 * kRadPerDeg), 2));
      CHECK(want / kRadPerDeg == Approx(-35.149).margin(1e-3));
      CHECK(proj.sensor_angle(*ray, 0) == Approx(want).margin(1e-12));
      CHECK(merid.sensor_angle(*ray, 0) == 0);
    }
    {
      // θ = 80°, φ = 0: e0 = (cos θ, 0, −sin θ), d × e0 = (0, 1, 0) in the camera frame, so light
      // at 30° shows at atan(tan 30° / cos 80°) = 73.26° when projected, 30° meridionally.
      auto ray = proj.ray(pixel_of(80 * kRadPerDeg, 0));
      REQUIRE(ray);
      const double want = std::atan(std::tan(30 * kRadPerDeg) / std::cos(80 * kRadPerDeg));
      CHECK(want / kRadPerDeg == Approx(73.26).margin(1e-2));
      CHECK(proj.sensor_angle(*ray, 30 * kRadPerDeg) == Approx(want).margin(1e-12));
      CHECK(merid.sensor_angle(*ray, 30 * kRadPerDeg) == 30 * kRadPerDeg);
      // −60° projects to atan(tan(−60°)/cos 80°) = −84.50°, inside (−90°, 90°].
      CHECK(proj.sensor_angle(*ray, -60 * kRadPerDeg) ==
            Approx(std::atan(std::tan(-60 * kRadPerDeg) / std::cos(80 * kRadPerDeg))).margin(1e-12));
      // 90° stays 90° (never −90°): the wrap is to (−π/2, π/2].
      CHECK(proj.sensor_angle(*ray, kPi / 2) == Approx(kPi / 2).margin(1e-12));
    }
    {
      // Near the axis the two agree.
      auto ray = proj.ray(pixel_of(1 * kRadPerDeg, 1.0));
      REQUIRE(ray);
      CHECK(proj.sensor_angle(*ray, 0.4) == Approx(0.4).margin(1e-3));
    }
  }
}

TEST_CASE("camera rejects a null lens or a non-rotation", "[camera]") {
  CHECK_THROWS_AS(Camera(nullptr, Eigen::Matrix3d::Identity()), std::invalid_argument);
  Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
  mirror(0, 0) = -1;
  CHECK_THROWS_AS(Camera(fisheye185(), mirror), std::invalid_argument);
}

TEST_CASE("meridional transport keeps the angle to the meridional plane: E·m = cos(a − φ), E·s = sin(a − φ)", "[camera]") {
  // On the sensor, light at angle a (from +x) makes a − φ with the radial direction at azimuth φ;
  // an ideal rotationally symmetric lens maps the radial direction to the meridional one m = ∂d/∂θ
  // and the tangential one to the sagittal s, so the world E-vector must make the same angle.
  Camera cam(fisheye185(), Eigen::Matrix3d::Identity());
  for (double theta : {0.2, 1.0, 1.55, 1.6})
    for (double phi : {0.5, 2.5, -1.0})
      for (double a : {0.0, 50 * kRadPerDeg, -80 * kRadPerDeg}) {
        auto ray = cam.ray(pixel_of(theta, phi));
        REQUIRE(ray);
        const Eigen::Vector3d m(std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi),
                                -std::sin(theta));
        const Eigen::Vector3d s(-std::sin(phi), std::cos(phi), 0);
        const Eigen::Vector3d e = std::cos(a) * ray->e0 + std::sin(a) * ray->d.cross(ray->e0);
        CHECK(e.dot(m) == Approx(std::cos(a - phi)).margin(1e-12));
        CHECK(e.dot(s) == Approx(std::sin(a - phi)).margin(1e-12));
      }
}

TEST_CASE("projected transport at exactly 90° off-axis: E along the axis has no sensor angle", "[camera]") {
  // θ = 90°, φ = 0: e0 = (0, 0, −1) in the camera frame projects to nothing; the documented rule
  // returns the meridional angle (0).
  Camera proj(fisheye185(), Eigen::Matrix3d::Identity(), Transport::projected);
  auto ray = proj.ray(pixel_of(kPi / 2, 0));
  REQUIRE(ray);
  CHECK((ray->e0 - Eigen::Vector3d(0, 0, -1)).norm() < 1e-12);
  CHECK(proj.sensor_angle(*ray, 0) == 0);
  // Any other angle keeps a component along d × e0 = +y only: it projects to 90°.
  CHECK(proj.sensor_angle(*ray, 0.3) == Approx(kPi / 2).margin(1e-12));
  CHECK(std::isfinite(proj.sensor_angle(*ray, 1e-13)));
  CHECK(proj.sensor_angle(*ray, kPi / 2) == Approx(kPi / 2).margin(1e-12));
  // Beyond 90° (the 185° lens' edge) the angles stay finite and in (−90°, 90°].
  auto edge = proj.ray(pixel_of(92.5 * kRadPerDeg, 0.7));
  REQUIRE(edge);
  for (double a = -1.5; a <= 1.5; a += 0.1) {
    const double s = proj.sensor_angle(*edge, a);
    CHECK(std::isfinite(s));
    CHECK(s > -kPi / 2);
    CHECK(s <= kPi / 2);
  }
}
