// Scene loading: good scenes give the values written; each class of bad input gives a SceneError
// that names the file, the line and column, and the key.
#include <catch2/catch.hpp>

#include <cmath>

#include "scene/scene.h"

using skypol::scene::parse_scene;
using skypol::scene::SceneError;

namespace {

const char* kGood = R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336

[time]
start = "2022-09-23T08:00:00+02:00"
end = "2022-09-23T09:00:00+02:00"
step_min = 30

[camera]
model = "equidistant"
focal_mm = 1.8
pitch_um = 3.45
width = 64
height = 48
fov_deg = 185
heading_deg = 30
)";

std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "bad.toml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("a scene's values arrive as written, with documented defaults", "[scene]") {
  const auto s = parse_scene(kGood, "good.toml");
  CHECK(s.site.latitude_deg == 43.28699);
  REQUIRE(s.times.size() == 3);  // 08:00, 08:30, 09:00 local = 06:00.. UTC
  CHECK(s.times[0].unix_seconds == 1663912800.0);  // 2022-09-23T06:00:00Z
  CHECK(s.times[2].unix_seconds - s.times[0].unix_seconds == 3600.0);
  const skypol::camera::Intrinsics k = skypol::scene::build_camera(s.camera)->lens().intrinsics();
  CHECK(k.fx == Approx(1.8e3 / 3.45).epsilon(1e-12));
  CHECK(k.cx == 31.5);  // pixel centres at integers: the image centre is (w−1)/2
  CHECK(k.cy == 23.5);
  CHECK(s.camera.heading_deg == 30);
  CHECK(s.sky.model == "rayleigh");
  CHECK(s.render.spp == 1);
  CHECK(s.output.path == "out/good.exr");
  CHECK(s.output.compression == "zip");
}

TEST_CASE("the camera description rebuilds the same camera", "[scene]") {
  const auto s = parse_scene(kGood, "good.toml");
  const auto again = skypol::scene::parse_camera(s.camera.description, "header");
  CHECK(again.heading_deg == s.camera.heading_deg);
  CHECK(again.description == s.camera.description);
  const auto a = skypol::scene::build_camera(s.camera), b = skypol::scene::build_camera(again);
  for (const Eigen::Vector2d& px : {Eigen::Vector2d(0, 0), Eigen::Vector2d(31.5, 23.5), Eigen::Vector2d(60.2, 3.7)}) {
    const auto ra = a->ray(px), rb = b->ray(px);
    REQUIRE(ra.has_value() == rb.has_value());
    if (ra) CHECK(ra->d == rb->d);  // bit for bit: the description is exact
  }
}

TEST_CASE("malformed TOML names the file and line", "[scene][errors]") {
  const std::string e = error_of(replace(kGood, "width = 64", "width = = 64"));
  CHECK_THAT(e, Catch::StartsWith("bad.toml:14:"));
  CHECK_THAT(e, Catch::Contains("TOML syntax"));
}

TEST_CASE("an unknown key is an error with the nearest known key", "[scene][errors]") {
  const std::string e = error_of(replace(kGood, "fov_deg = 185", "fov_dge = 185"));
  CHECK_THAT(e, Catch::StartsWith("bad.toml:16:1: error: unknown key 'camera.fov_dge'"));
  CHECK_THAT(e, Catch::Contains("did you mean 'camera.fov_deg'?"));
}

TEST_CASE("an unknown section is an error", "[scene][errors]") {
  const std::string e = error_of(std::string(kGood) + "\n[sensr]\nexposure_us = 3\n");
  CHECK_THAT(e, Catch::Contains("unknown key 'sensr'"));
}

TEST_CASE("a value out of range states the range", "[scene][errors]") {
  const std::string e = error_of(replace(kGood, "latitude_deg = 43.28699", "latitude_deg = 95"));
  CHECK_THAT(e, Catch::StartsWith("bad.toml:2:16: error: key 'site.latitude_deg': value 95 out of range [-90, 90]"));
}

TEST_CASE("a value of the wrong type says what was expected", "[scene][errors]") {
  const std::string e = error_of(replace(kGood, "width = 64", "width = \"wide\""));
  CHECK_THAT(e, Catch::Contains("key 'camera.width': expected an integer, found a string"));
  CHECK_THAT(e, Catch::StartsWith("bad.toml:14:"));
}

TEST_CASE("a missing required key or section is named", "[scene][errors]") {
  CHECK_THAT(error_of(replace(kGood, "longitude_deg = 5.40336", "")),
             Catch::Contains("missing key 'site.longitude_deg'"));
  CHECK_THAT(error_of(replace(kGood, "[site]", "[place]")), Catch::Contains("missing section [site]"));
}

TEST_CASE("an unknown enumerated value lists the legal ones", "[scene][errors]") {
  const std::string e = error_of(replace(kGood, "model = \"equidistant\"", "model = \"fisheye\""));
  CHECK_THAT(e, Catch::Contains("unknown value 'fisheye'"));
  CHECK_THAT(e, Catch::Contains("'equisolid'"));
}

TEST_CASE("an instant that cannot be parsed is an error at its key", "[scene][errors]") {
  const std::string e = error_of(replace(kGood, "2022-09-23T09:00:00+02:00", "23/09/2022 9h"));
  CHECK_THAT(e, Catch::StartsWith("bad.toml:7:7: error: key 'time.end':"));
}

TEST_CASE("a missing scene file is an error naming it", "[scene][errors]") {
  try {
    skypol::scene::load_scene("/nonexistent/scene.toml");
    FAIL("no error");
  } catch (const SceneError& e) {
    CHECK_THAT(e.what(), Catch::StartsWith("/nonexistent/scene.toml: error: cannot open scene file"));
  }
}
