// The conventions of skypole/estimate.h: level frame, heading, latitude, hemisphere, scoring.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "camera/orientation.h"
#include "sky/units.h"
#include "skypole/classic.h"
#include "skypole/estimate.h"
#include "skypole/great_circle.h"
#include "skypole/invariance.h"
#include "skypole/sun_vector.h"
#include "skypole/sky_images.h"
#include "synthetic_stack.h"

using namespace skypol;

namespace {

// A small stack just to get a SkyImages with a lens and a level frame.
stack::Stack tiny_stack(double lat, double heading, double tilt, double roll) {
  testing::SyntheticSpec spec;
  spec.latitude_deg = lat;
  spec.heading_deg = heading;
  spec.tilt_deg = tilt;
  spec.roll_deg = roll;
  spec.size = 64;
  spec.times = {sky::parse_iso8601("2022-09-23T10:00:00Z")};
  return testing::make_stack(spec);
}
}  // namespace

TEST_CASE("heading composes as Rz(-heading) times the level frame", "[skypole]") {
  // The level-frame convention relies on this property of camera/orientation.h.
  for (double h : {0.0, 30.0, 145.0, 300.0})
    for (double tilt : {0.0, 20.0, 90.0})
      for (double roll : {0.0, -15.0, 40.0}) {
        const Eigen::Matrix3d rz =
            Eigen::AngleAxisd(-h * kRadPerDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        const Eigen::Matrix3d a = camera::world_from_heading_tilt_roll(h, tilt, roll);
        const Eigen::Matrix3d b = rz * camera::world_from_heading_tilt_roll(0, tilt, roll);
        CHECK((a - b).cwiseAbs().maxCoeff() < 1e-12);
      }
}

TEST_CASE("the true pole turns into the true heading and latitude", "[skypole]") {
  // Expected values come from the scene (heading, latitude), not from the estimator code.
  for (double lat : {43.28699, -33.87, 0.5, -70.0})
    for (double heading : {0.0, 37.0, 181.0, 359.0})
      for (auto [tilt, roll] : {std::pair{0.0, 0.0}, std::pair{25.0, 10.0}}) {
        const stack::Stack stack = tiny_stack(lat, heading, tilt, roll);
        const skypole::SkyImages sky =
            skypole::prepare_sky_images(stack, {}, 1, "test");
        const scene::Truth& t = stack.frames.front().truth;
        const Eigen::Vector3d ncp_world(0, std::cos(lat * kRadPerDeg), std::sin(lat * kRadPerDeg));
        const Eigen::Vector3d ncp_cam = t.world_from_camera.transpose() * ncp_world;
        const skypole::PoleEstimate e = skypole::make_estimate("truth", sky, ncp_cam, {});
        INFO("lat " << lat << " heading " << heading << " tilt " << tilt << " roll " << roll);
        REQUIRE(e.valid);
        CHECK(e.is_north == (lat >= 0));
        CHECK(e.latitude_deg == Approx(lat).margin(1e-9));
        CHECK(e.altitude_deg == Approx(std::abs(lat)).margin(1e-9));
        REQUIRE(e.heading_deg);
        CHECK(skypole::wrap180(*e.heading_deg - heading) == Approx(0).margin(1e-9));
        const skypole::Score s = skypole::score(e, t);
        CHECK(s.angular_error_deg == Approx(0).margin(1e-6));
        CHECK(s.latitude_error_deg == Approx(0).margin(1e-9));
        REQUIRE(s.bearing_error_deg);
        CHECK(*s.bearing_error_deg == Approx(0).margin(1e-9));
      }
}

TEST_CASE("an observer at a geographic pole gets no bearing, never a number", "[skypole]") {
  const stack::Stack stack = tiny_stack(90.0, 10.0, 0, 0);
  const skypole::SkyImages sky = skypole::prepare_sky_images(stack, {}, 1, "test");
  const skypole::PoleEstimate e =
      skypole::make_estimate("truth", sky, Eigen::Vector3d(0, 0, 1), {});
  CHECK(e.valid);
  CHECK_FALSE(e.heading_deg.has_value());
  CHECK(e.note.find("undefined") != std::string::npos);
  CHECK(e.latitude_deg == Approx(90));
  const skypole::Score s = skypole::score(e, stack.frames.front().truth);
  CHECK_FALSE(s.bearing_error_deg.has_value());
}

TEST_CASE("scores wrap the bearing error and see a wrong hemisphere", "[skypole]") {
  const stack::Stack stack = tiny_stack(43.28699, 350.0, 0, 0);
  const skypole::SkyImages sky = skypole::prepare_sky_images(stack, {}, 1, "test");
  const scene::Truth& t = stack.frames.front().truth;
  const double lat = 43.28699 * kRadPerDeg;
  // The NCP rotated 15° east: heading estimate 350 − 15 = 335, error −15 (not 345).
  const Eigen::Vector3d off(std::sin(15 * kRadPerDeg) * std::cos(lat), std::cos(15 * kRadPerDeg) * std::cos(lat),
                            std::sin(lat));
  const skypole::PoleEstimate e =
      skypole::make_estimate("t", sky, t.world_from_camera.transpose() * off, {});
  const skypole::Score s = skypole::score(e, t);
  REQUIRE(s.bearing_error_deg);
  CHECK(*s.bearing_error_deg == Approx(-15).margin(1e-9));
  // Claiming the antipode (the SCP seen as the NCP): angular error 180°.
  const skypole::PoleEstimate w = skypole::make_estimate(
      "t", sky, -(t.world_from_camera.transpose() * t.pole_enu), {});
  CHECK(skypole::score(w, t).angular_error_deg == Approx(180).margin(1e-6));
  CHECK_THROWS_AS(skypole::score(skypole::invalid_estimate("t", "because"), t),
                  std::invalid_argument);
  CHECK(skypole::wrap180(190) == Approx(-170));
  CHECK(skypole::wrap180(-180) == Approx(180));
  CHECK(skypole::wrap360(-10) == Approx(350));
  CHECK(skypole::format_heading(359.9996, 3) == "0.000");
  CHECK(skypole::format_heading(359.9994, 3) == "359.999");
  CHECK(skypole::format_heading(-0.0001, 3) == "0.000");
  CHECK(skypole::format_heading(-90, 1) == "270.0");
}

TEST_CASE("the masked disk filter averages only valid pixels", "[skypole]") {
  const stack::Stack stack = tiny_stack(43.28699, 0, 0, 0);
  const skypole::SkyImages sky = skypole::prepare_sky_images(stack, {}, 1, "test");
  std::vector<float> img(sky.pixels(), 7.0f);
  for (std::size_t i = 0; i < img.size(); ++i)
    if (!sky.valid[i]) img[i] = 1000.0f;  // must never leak into the average
  const std::vector<float> out = skypole::disk_filter(img, sky, 3.0);
  for (std::size_t i = 0; i < img.size(); ++i)
    if (sky.valid[i]) REQUIRE(out[i] == Approx(7.0f));
  CHECK(skypole::default_filter_radius_px(256, 256) == 1.0);
  CHECK(skypole::default_filter_radius_px(1224, 1024) == 5.0);
}

TEST_CASE("option names round-trip and bad names list the legal ones", "[skypole]") {
  using namespace skypol::skypole;
  for (const auto h : {Hemisphere::automatic, Hemisphere::north, Hemisphere::south})
    CHECK(parse_hemisphere(hemisphere_name(h)) == h);
  for (const auto r : {Refine::per_frame, Refine::corotating, Refine::automatic})
    CHECK(parse_refine(refine_name(r)) == r);
  for (const auto d : {DriftModel::none, DriftModel::fit, DriftModel::automatic})
    CHECK(parse_drift_model(drift_model_name(d)) == d);
  CHECK(parse_threshold_mode(threshold_mode_name(ThresholdMode::relative)) == ThresholdMode::relative);
  CHECK(parse_sun_source(sun_source_name(SunSource::dolp)) == SunSource::dolp);
  CHECK(parse_pole_from_sun(pole_from_sun_name(PoleFromSun::ephemeris)) == PoleFromSun::ephemeris);
  CHECK(parse_detrend("auto") == Detrend::automatic);
  CHECK(detrend_name(Detrend::linear) == "linear");
  CHECK_THROWS_WITH(parse_hemisphere("west"),
                    "unknown hemisphere \"west\" (expected one of automatic, north, south)");
  CHECK_THROWS_WITH(parse_sun_source("auto"), Catch::Contains("expected one of aolp, dolp"));
}

// docs/conventions.md, "Celestial pole and hemisphere": north at latitude ≥ 0, and at the equator
// north is chosen. An estimate cannot tell latitude 0 from −0.001°, so an NCP estimated within
// 0.1° below the horizon is still reported as the north pole (with its latitude as measured); only
// further south does the report switch to the south pole.
TEST_CASE("the equator rule: an NCP a hair below the horizon is reported north", "[skypole][hemisphere]") {
  const stack::Stack stack = tiny_stack(0.0, 30.0, 0, 0);
  const skypole::SkyImages sky = skypole::prepare_sky_images(stack, {}, 1, "test");
  const scene::Truth& t = stack.frames.front().truth;
  for (double lat : {0.0, -0.001, -0.05, 0.001}) {
    const Eigen::Vector3d ncp_cam =
        t.world_from_camera.transpose() * Eigen::Vector3d(0, std::cos(lat * kRadPerDeg), std::sin(lat * kRadPerDeg));
    const skypole::PoleEstimate e = skypole::make_estimate("test", sky, ncp_cam, {});
    INFO("NCP altitude " << lat);
    CHECK(e.is_north);
    CHECK(e.latitude_deg == Approx(lat).margin(1e-9));
    CHECK(skypole::wrap180(*e.heading_deg - 30.0) == Approx(0).margin(1e-9));
    CHECK(skypole::score(e, t).angular_error_deg == Approx(std::abs(lat)).margin(1e-6));
  }
  for (double lat : {-0.2, -1.0}) {  // beyond the band: the south pole, as before
    const Eigen::Vector3d ncp_cam =
        t.world_from_camera.transpose() * Eigen::Vector3d(0, std::cos(lat * kRadPerDeg), std::sin(lat * kRadPerDeg));
    const skypole::PoleEstimate e = skypole::make_estimate("test", sky, ncp_cam, {});
    INFO("NCP altitude " << lat);
    CHECK_FALSE(e.is_north);
    CHECK(e.latitude_deg == Approx(lat).margin(1e-9));
    CHECK(skypole::wrap180(*e.heading_deg - 30.0) == Approx(0).margin(1e-9));
  }
}

// skypole/README.md, "North or south": a hint decides when the data cannot, and loses (with a note
// saying so) when the sun's rotation contradicts it decisively.
TEST_CASE("decide_hemisphere: the data win over a contradicting hint only when decisive", "[skypole][hemisphere]") {
  // Suns turning about +z as the sky does about the NCP: (s1 × s2)·NCP < 0 (estimate.h).
  const auto suns_every = [](double step_deg) {
    std::vector<std::optional<Eigen::Vector3d>> suns;
    const double dec = 10 * kRadPerDeg;
    for (int k = -4; k <= 4; ++k) {
      const double w = k * step_deg * kRadPerDeg;
      suns.emplace_back(Eigen::Vector3d(-std::cos(dec) * std::sin(w), -std::cos(dec) * std::cos(w), std::sin(dec)));
    }
    return suns;
  };
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  const auto day = suns_every(15);
  const skypole::HemisphereDecision automatic = skypole::decide_hemisphere(day, axis, skypole::Hemisphere::automatic);
  REQUIRE(automatic.ok);
  CHECK(automatic.is_north);

  const skypole::HemisphereDecision against = skypole::decide_hemisphere(day, axis, skypole::Hemisphere::south);
  CHECK(against.ok);
  CHECK(against.is_north);  // the data win
  CHECK(against.source.find("overriding the hint") != std::string::npos);
  CHECK(against.source.find("south") != std::string::npos);

  const skypole::HemisphereDecision agreed = skypole::decide_hemisphere(day, axis, skypole::Hemisphere::north);
  CHECK(agreed.is_north);
  CHECK(agreed.source == "hint");

  // No sun in view, or a sun that hardly moves: the hint decides.
  const std::vector<std::optional<Eigen::Vector3d>> none(5);
  const skypole::HemisphereDecision blind = skypole::decide_hemisphere(none, axis, skypole::Hemisphere::south);
  CHECK(blind.ok);
  CHECK_FALSE(blind.is_north);
  CHECK(blind.source == "hint");
  const skypole::HemisphereDecision still = skypole::decide_hemisphere(suns_every(0.001), axis, skypole::Hemisphere::south);
  CHECK_FALSE(still.is_north);
  CHECK(still.source == "hint");

  // A midnight sun: frames at 0, 13 and 14 h (hour angles 0°, 195°, 210°). Two of the three pairs
  // are more than 12 h apart and see the sun turned the short way round (s_i × s_j ∝ −sin Δω·NCP):
  // counted as they come they outvote the third and say south, decisively; with the frame times
  // they count reversed and all three say north.
  const double dec = 10 * kRadPerDeg;
  std::vector<std::optional<Eigen::Vector3d>> midnight;
  for (const double w_deg : {0.0, 195.0, 210.0}) {
    const double w = w_deg * kRadPerDeg;
    midnight.emplace_back(Eigen::Vector3d(-std::cos(dec) * std::sin(w), -std::cos(dec) * std::cos(w), std::sin(dec)));
  }
  const skypole::HemisphereDecision untimed = skypole::decide_hemisphere(midnight, axis, skypole::Hemisphere::automatic);
  REQUIRE(untimed.ok);
  CHECK_FALSE(untimed.is_north);
  const skypole::HemisphereDecision timed =
      skypole::decide_hemisphere(midnight, axis, skypole::Hemisphere::automatic, {0.0, 13 * 3600.0, 14 * 3600.0});
  REQUIRE(timed.ok);
  CHECK(timed.is_north);
}
