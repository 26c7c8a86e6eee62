// Guard rails: a render in which no pixel sees the sky is refused before anything is written,
// naming the likely key; progress goes to a terminal only, with its rate and time left.
#include <catch2/catch.hpp>

#include "cli/cli_harness.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::run_shell;
using skypol::test::skypol_bin;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

const char* kScene = R"([site]
latitude_deg = 43.3
longitude_deg = 5.4

[time]
start = "2022-06-21T06:00:00Z"
end = "2022-06-21T09:00:00Z"
step_min = 60

[camera]
model = "equidistant"
width = 120
height = 100
focal_mm = 1.8
pitch_um = 27.6
fov_deg = 185
)";

}  // namespace

TEST_CASE("a camera whose pixels see no sky is refused, naming the likely key", "[cli][guard]") {
  TempDir dir;
  const std::string scene = dir.write("s.toml", kScene);
  const std::string out = (dir.path / "out" / "s.exr").string();
  REQUIRE(run("render -q " + scene + " -o " + out).code == 0);  // the sane camera renders
  fs::remove_all(dir.path / "out");

  SECTION("focal_mm in metres") {
    const Result r = run("render -q " + scene + " --set camera.focal_mm=0.0018 -o " + out);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("no pixel of the 120x100 image sees the sky"));
    CHECK_THAT(r.out, Catch::Contains("camera.focal_mm = 0.0018") && Catch::Contains("not metres"));
  }
  SECTION("focal_mm in metres on a full-size sensor: four pixels of five million") {
    const std::string preset = dir.write("preset.toml", std::string(kScene).substr(0, std::string(kScene).find("[camera]")) +
                                                            "[camera]\nlens_preset = \"fujinon_fe185c057ha1\"\n"
                                                            "sensor_preset = \"sony_imx250mzr\"\nfocal_mm = 0.0018\n");
    const Result r = run("render -q " + preset + " -o " + out);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("only 4 pixel(s) of the 2448x2048 image see the sky"));
    CHECK_THAT(r.out, Catch::Contains("camera.focal_mm = 0.0018"));
    CHECK_THAT(r.out, Catch::Contains("preset.toml:13:"));  // at the line that writes focal_mm
  }
  SECTION("a camera facing the ground") {
    const Result r = run("render -q " + scene + " --set camera.tilt_deg=180 --set camera.fov_deg=120 -o " + out);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("below the horizon") && Catch::Contains("camera.tilt_deg (180"));
  }
  CHECK_FALSE(fs::exists(dir.path / "out" / "s.exr"));
}

TEST_CASE("progress is drawn on a terminal, with rate and time left, and never into a pipe", "[cli][guard]") {
  TempDir dir;
  const std::string scene = dir.write("s.toml", kScene);
  const std::string out = (dir.path / "s.exr").string();
  const Result piped = run("render " + scene + " -o " + out);
  REQUIRE(piped.code == 0);
  CHECK(piped.out.find('\r') == std::string::npos);
  CHECK_THAT(piped.out, Catch::Contains("wrote"));
  // script(1) gives the command a pseudo-terminal, as a user's shell would.
  if (run_shell("command -v script").code != 0) {
    WARN("script(1) is not installed: the terminal case is not checked");
    return;
  }
  const Result tty = run_shell("script -qec '" + skypol_bin() + " render " + scene + " -o " + out + "' /dev/null");
  INFO(tty.out);
  CHECK(tty.code == 0);
  CHECK_THAT(tty.out, Catch::Contains("4/4 frames") && Catch::Contains("/s"));
  const Result est = run_shell("script -qec '" + skypol_bin() + " estimate " + out + " -m great_circle,sun_dolp' /dev/null");
  INFO(est.out);
  CHECK_THAT(est.out, Catch::Contains("2/2 methods"));
}
