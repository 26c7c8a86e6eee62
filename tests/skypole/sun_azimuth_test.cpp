// sun_azimuth: the celestial fix from the suns' azimuths and the clock (skypole/sun_azimuth.h).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "sky/sun.h"
#include "sky/units.h"
#include "skypole/sun_azimuth.h"
#include "skypole/sun_vector.h"
#include "fixtures.h"

using namespace skypol;

namespace {

// The suns an observer at `site` sees at `times`, in the level frame of a camera turned to
// `heading_deg` (world azimuth = level azimuth + heading, estimate.h).
std::vector<Eigen::Vector3d> level_suns(const sky::Site& site, const std::vector<sky::Instant>& times,
                                        double heading_deg) {
  const Eigen::Matrix3d level_from_world =
      Eigen::AngleAxisd(heading_deg * kRadPerDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> out;
  for (const sky::Instant& t : times) out.push_back(level_from_world * sky::sun_position(site, t).direction);
  return out;
}

double wrap180(double a) { return std::remainder(a, 360.0); }

}  // namespace

TEST_CASE("the azimuth fix recovers latitude, longitude and heading from exact suns", "[skypole][sun_azimuth]") {
  struct Case {
    const char* label;
    sky::Site site;
    const char* start;
    const char* end;
    double heading;
  };
  // The fix models the sun's parallax (8.8″) but not its diurnal aberration (≤ 0.32″, 1e-4°) nor the
  // ellipsoid's tilt of the observer's offset (≤ 0.19° of the 8.8″).
  const Case cases[] = {
      {"Marseille equinox day", {43.28699, 5.40336, 60}, "2022-09-23T08:00Z", "2022-09-23T16:00Z", 37},
      {"Sydney winter", {-33.87, 151.21, 0}, "2023-06-20T22:00Z", "2023-06-21T04:00Z", 200},
      {"Quito, 1 km off the equator", {-0.01, -78.5, 2800}, "2022-12-01T13:00Z", "2022-12-01T20:00Z", 95},
      {"Tromsø midnight sun", {69.65, 18.96, 0}, "2023-06-21T06:00Z", "2023-06-21T14:00Z", 310},
      // The sun passes 0.03° from the zenith at noon: that frame's azimuth counts for nothing.
      {"Tropic of Cancer at the solstice", {23.41, 45.0, 0}, "2023-06-21T05:00Z", "2023-06-21T13:00Z", 10},
  };
  for (const Case& c : cases) {
    INFO(c.label);
    const auto times = testing::times_every(c.start, c.end, 30);
    const skypole::AzimuthFix fix = skypole::fix_from_sun_azimuths(level_suns(c.site, times, c.heading), times);
    REQUIRE(fix.ok);
    CHECK(std::abs(fix.latitude_deg - c.site.latitude_deg) < 5e-4);
    CHECK(std::abs(wrap180(fix.longitude_deg - c.site.longitude_deg)) < 5e-4 / std::cos(c.site.latitude_deg * kRadPerDeg));
    CHECK(std::abs(wrap180(fix.heading_deg - c.heading)) < 5e-4);
    CHECK(fix.rms_rad < 1e-5);
  }
}

TEST_CASE("the azimuth fix ignores the suns' elevations: a shared elevation bias leaves it unmoved",
          "[skypole][sun_azimuth]") {
  // Multiple scattering moves the suns found from the AoLP along their verticals, alike in every
  // frame; the fix reads azimuths only, so lifting every sun by 1.5° changes nothing.
  const sky::Site site{43.28699, 5.40336, 60};
  const auto times = testing::times_every("2022-09-23T07:00Z", "2022-09-23T15:00Z", 20);
  std::vector<Eigen::Vector3d> suns = level_suns(site, times, 120), lifted;
  for (const Eigen::Vector3d& s : suns) {
    const double az = std::atan2(s.x(), s.y()), el = std::asin(s.z()) + 1.5 * kRadPerDeg;
    lifted.push_back(Eigen::Vector3d(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)));
  }
  const skypole::AzimuthFix a = skypole::fix_from_sun_azimuths(suns, times);
  const skypole::AzimuthFix b = skypole::fix_from_sun_azimuths(lifted, times);
  REQUIRE(a.ok);
  REQUIRE(b.ok);
  CHECK(std::abs(a.latitude_deg - b.latitude_deg) < 1e-3);
  CHECK(std::abs(wrap180(a.heading_deg - b.heading_deg)) < 1e-3);
}

TEST_CASE("the azimuth fix refuses fewer than 3 suns, and suns no site explains", "[skypole][sun_azimuth]") {
  const sky::Site site{43.28699, 5.40336, 60};
  const auto times = testing::times_every("2022-09-23T08:00Z", "2022-09-23T09:00Z", 30);
  auto suns = level_suns(site, times, 0);
  CHECK_FALSE(skypole::fix_from_sun_azimuths({suns[0], suns[1]}, {times[0], times[1]}).ok);
  // The sun standing still in the sky for two hours: no observer sees that.
  const auto still = testing::times_every("2022-09-23T08:00Z", "2022-09-23T10:00Z", 30);
  const std::vector<Eigen::Vector3d> fixed(still.size(), suns[0]);
  const skypole::AzimuthFix f = skypole::fix_from_sun_azimuths(fixed, still);
  INFO(f.why << " rms " << f.rms_rad);
  CHECK((!f.ok || f.rms_rad > 0.01));
}

TEST_CASE("sun_azimuth finds the pole on a Rayleigh day and on Berry's sky with its neutral points",
          "[skypole][sun_azimuth]") {
  for (const char* model : {"rayleigh", "berry"}) {
    INFO(model);
    testing::SyntheticSpec spec = testing::paper_spec(63);
    spec.sky_model = model;
    spec.size = 192;
    const stack::Stack stack = testing::make_stack(spec);
    const skypole::PoleEstimate e = skypole::estimate_sun_azimuth(stack);
    INFO(e.why_invalid);
    REQUIRE(e.valid);
    const skypole::Score s = skypole::score(e, stack.frames.front().truth);
    CHECK(s.angular_error_deg < 0.05);
  }
}

TEST_CASE("the azimuth fix at a geographic pole: latitude holds, longitude and heading trade off",
          "[skypole][sun_azimuth][hard]") {
  // At the pole the sun's azimuth turns at the hour angle's rate whatever the longitude, so only
  // longitude − heading is fixed; the latitude still is, and nothing becomes NaN.
  const sky::Site pole{90, 0, 0};
  const auto times = testing::times_every("2022-06-21T00:00Z", "2022-06-21T12:00Z", 60);
  const skypole::AzimuthFix fix = skypole::fix_from_sun_azimuths(level_suns(pole, times, 40), times);
  INFO(fix.why);
  REQUIRE(fix.ok);
  CHECK(fix.latitude_deg > 89.9);
  CHECK(std::isfinite(fix.longitude_deg));
  CHECK(std::isfinite(fix.heading_deg));
}
