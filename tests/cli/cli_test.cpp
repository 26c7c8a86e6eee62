// The skypol executable as a user runs it: exit codes, messages naming file/line/key, no partial
// output after an error, and the end-to-end path scene → stack → estimate on a small scene.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "cli/cli_harness.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string kSmallScene = std::string(skypol::test::kMarseilleSite) + R"(
[time]
start = "2022-09-23T06:00:00Z"
end = "2022-09-23T17:00:00Z"
step_min = 60

[camera]
model = "equidistant"
focal_mm = 1.8
pitch_um = 13.8       # the paper's sensor binned 4x4
width = 612
height = 512
fov_deg = 185
heading_deg = 30
)";

}  // namespace

TEST_CASE("run renders a scene and prints the estimate beside the truth", "[cli]") {
  TempDir dir;
  const std::string scene = dir.write("small.toml", kSmallScene);
  const std::string out = (dir.path / "small.exr").string();
  const Result r = run("run -q " + scene + " -o " + out + " --json");
  INFO(r.out);
  REQUIRE(r.code == 0);
  CHECK(fs::exists(out));
  CHECK_THAT(r.out, Catch::Contains("\"true_latitude_deg\": 43.286990"));
  CHECK_THAT(r.out, Catch::Contains("\"true_heading_deg\": 30.000000"));
  // The classic estimator finds the pole of a noise-free stack within a degree.
  const auto lat_err = std::stod(r.out.substr(r.out.find("\"latitude_error_deg\": ") + 22));
  const auto bearing_err = std::stod(r.out.substr(r.out.find("\"bearing_error_deg\": ") + 21));
  CHECK(std::abs(lat_err) < 1.0);
  CHECK(std::abs(bearing_err) < 1.0);

  const Result info = run("info " + out);
  REQUIRE(info.code == 0);
  CHECK_THAT(info.out, Catch::Contains("12 frame(s), 612x512 px"));
  CHECK_THAT(info.out, Catch::Contains("2022-09-23T11:00:00Z"));
}

TEST_CASE("a bad scene exits non-zero with file, line and key, and writes nothing", "[cli][errors]") {
  TempDir dir;
  std::string text = kSmallScene;
  text.replace(text.find("fov_deg = 185"), 13, "fov_deg = 400");
  const std::string scene = dir.write("bad.toml", text);
  const std::string out = (dir.path / "bad.exr").string();
  const Result r = run("render " + scene + " -o " + out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains(scene + ":16:11: error: key 'camera.fov_deg': value 400 out of range [1, 360]"));
  CHECK_FALSE(fs::exists(out));
  CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()) == 1);  // only the scene
}

TEST_CASE("a missing scene or stack file is named", "[cli][errors]") {
  const Result r = run("render /nonexistent.toml");
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("/nonexistent.toml: error: cannot open scene file"));
  const Result s = run("estimate /nonexistent.exr");
  CHECK(s.code == 2);
  CHECK_THAT(s.out, Catch::Contains("/nonexistent.exr: error: cannot read stack"));
}

TEST_CASE("an unknown estimator lists the known ones", "[cli][errors]") {
  const Result r = run("estimate whatever.exr --method astrology");
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("unknown method 'astrology' (expected one of classic"));
}

TEST_CASE("sun prints ERFA's sun for a site and instant", "[cli]") {
  // Marseille at 11:30 UTC on the September 2022 equinox: the sun is near the meridian, at about
  // 90° − 43.29° + δ ≈ 46.5° elevation (δ ≈ −0.17°).
  const Result r = run("sun --lat 43.28699 --lon 5.40336 -t 2022-09-23T13:30:00+02:00");
  REQUIRE(r.code == 0);
  CHECK_THAT(r.out, Catch::Contains("time          2022-09-23T11:30:00Z"));
  const double el = std::stod(r.out.substr(r.out.find("elevation") + 9));
  CHECK(el == Approx(90 - 43.28699 - 0.17).margin(0.05));
  const Result bad = run("sun --lat 95 --lon 0 -t 2022-09-23T12:00:00Z");
  CHECK(bad.code == 2);
  CHECK_THAT(bad.out, Catch::Contains("latitude"));
}

TEST_CASE("sun reproduces NREL SPA's worked example from SPA's own inputs", "[cli][spa]") {
  // Reda & Andreas (NREL/TP-560-34302): 2003-10-17 12:30:30 local time −7 h, 39.742476 N,
  // 105.1786 W, 1830.14 m, 820 hPa, 11 °C, ΔT 67 s, ΔUT1 0 → zenith 50.11162°, azimuth 194.34024°.
  const std::string golden = "sun --lat 39.742476 --lon -105.1786 --height 1830.14 -t 2003-10-17T12:30:30-07:00 "
                             "--pressure 820 --temperature 11 --dut1 0";
  const std::string spa = golden + " --delta-t 67";
  const auto number_after = [](const std::string& out, const std::string& key) {
    return std::stod(out.substr(out.find(key) + key.size()));
  };
  const Result r = run(spa);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.out, Catch::Contains("(refracted, spa)"));
  CHECK(number_after(r.out, "zenith angle") == Approx(50.11162).margin(5e-4));
  CHECK(number_after(r.out, "azimuth") == Approx(194.34024).margin(5e-4));

  // ERFA's refraction, selectable, with the inputs only it uses.
  const Result e = run(spa + " --refraction erfa --humidity 0 --wavelength 0.55");
  REQUIRE(e.code == 0);
  CHECK_THAT(e.out, Catch::Contains("(refracted, erfa)"));
  CHECK(number_after(e.out, "zenith angle") == Approx(50.11162).margin(1e-3));
  CHECK(std::abs(number_after(e.out, "zenith angle") - number_after(r.out, "zenith angle")) > 5e-4);

  const Result bad = run(spa + " --refraction bennett");
  CHECK(bad.code != 0);
  CHECK_THAT(bad.out, Catch::Contains("spa") && Catch::Contains("erfa"));
  const Result far = run(golden + " --delta-t 9000");
  CHECK(far.code != 0);
  CHECK_THAT(far.out, Catch::Contains("ΔT"));
}
