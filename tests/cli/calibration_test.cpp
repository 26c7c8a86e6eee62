// A calibration file through the executable: a stack rendered with one is estimated after the
// file has moved away (its text is in the header), with the same answer; `skypol lens` reads the
// keys; a bad calibration file exits 2 naming the file and line.
#include <catch2/catch.hpp>

#include <regex>

#include "cli/cli_harness.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string kScene = std::string(skypol::test::kMarseilleSite) + R"(
[time]
dates = "2022-09-23"
zone = "Z"
day_start = "08:00"
day_end = "16:00"
step_min = 60

[camera]
calibration = "cal/cameras.txt"
calibration_format = "colmap"
calibration_camera = 2
binning = 4
heading_deg = 25

[output]
channels = ["S0", "S1", "S2", "DoLP", "AoLP", "mask"]
)";

const char* kCameras =
    "# COLMAP cameras.txt\n"
    "1 OPENCV_FISHEYE 1224 1024 261.0 260.8 612.3 511.9 0.0061 -0.0018 0.00031 -0.00002\n"
    "2 THIN_PRISM_FISHEYE 1224 1024 261.0 260.8 612.3 511.9 0.0061 -0.0018 0.00012 -0.00008 0.00031 -0.00002 "
    "0.00021 -0.00011\n";

}  // namespace

TEST_CASE("a stack rendered from a calibration file estimates after the file is gone, with the same answer", "[cli][calibration]") {
  TempDir dir;
  fs::create_directories(dir.path / "cal");
  dir.write("cal/cameras.txt", kCameras);
  const std::string scene = dir.write("scene.toml", kScene);
  const std::string stack = (dir.path / "s.exr").string();
  const Result r = run("render -q " + scene + " -o " + stack);
  INFO(r.out);
  REQUIRE(r.code == 0);
  const Result before = run("estimate " + stack + " -m great_circle --json");
  INFO(before.out);
  REQUIRE(before.code == 0);
  fs::rename(dir.path / "cal", dir.path / "moved");
  const Result after = run("estimate " + stack + " -m great_circle --json");
  INFO(after.out);
  REQUIRE(after.code == 0);
  // The same answer, to the printed digits (only the run time may differ).
  const std::regex seconds("\"seconds\": [0-9.]+");
  CHECK(std::regex_replace(after.out, seconds, "") == std::regex_replace(before.out, seconds, ""));
  // The pole is found: the lens the header rebuilt is the one that rendered.
  CHECK(after.out.find("\"valid\": true") != std::string::npos);
  const Result info = run("info " + stack);
  CHECK(info.out.find("THIN_PRISM_FISHEYE") != std::string::npos);
}

TEST_CASE("skypol lens reads a calibration; bad calibration files exit 2 with file and line", "[cli][calibration]") {
  TempDir dir;
  fs::create_directories(dir.path / "cal");
  dir.write("cal/cameras.txt", kCameras);
  const std::string scene = dir.write("scene.toml", kScene);
  const Result lens = run("lens " + scene);
  INFO(lens.out);
  CHECK(lens.code == 0);
  CHECK(lens.out.find("thin_prism_fisheye") != std::string::npos);

  struct Bad {
    std::string file, expect;
  };
  const std::vector<Bad> bad = {
      {"# x\n2 FISHEYE_X 1224 1024 1 2 3\n", "cal/cameras.txt:2: COLMAP camera model \"FISHEYE_X\" is not supported"},
      {"2 THIN_PRISM_FISHEYE 1224 1024 261 261 612 512 0 0 0 0 0 0 0\n", "cal/cameras.txt:1: COLMAP THIN_PRISM_FISHEYE needs 12 parameters"},
      {"\n\n2 THIN_PRISM_FISHEYE 1224 1024 261 261 612 512 0 0 0 0 0 0 0 1e\n", "cal/cameras.txt:3: COLMAP camera line: parameter \"1e\" is not a number"},
  };
  for (const Bad& b : bad) {
    INFO(b.file);
    dir.write("cal/cameras.txt", b.file);
    const Result r = run("render -q " + scene + " -o " + (dir.path / "bad.exr").string());
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("scene.toml:13") && Catch::Contains("camera.calibration") && Catch::Contains(b.expect));
    CHECK_FALSE(fs::exists(dir.path / "bad.exr"));
  }
  fs::remove(dir.path / "cal/cameras.txt");
  const Result missing = run("lens " + scene);
  CHECK(missing.code == 2);
  CHECK_THAT(missing.out, Catch::Contains("camera.calibration") && Catch::Contains("no such file"));
}
