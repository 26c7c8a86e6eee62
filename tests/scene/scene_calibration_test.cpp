// [camera] calibration = "...": a calibration file of another tool becomes the lens, its text
// travels in the canonical description (so a stack's header needs no file), and its errors are
// reported at the key with the calibration file's own line.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "scene/scene.h"

using namespace skypol;
using scene::parse_scene;
using scene::SceneError;
namespace fs = std::filesystem;

namespace {

const std::string kHead = R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336

[time]
instants = ["2022-09-23T10:00:00Z"]

)";

struct Folder {
  fs::path path = fs::temp_directory_path() / ("skypol-calib-" + std::to_string(::getpid()));
  Folder() { fs::create_directories(path / "cams"); }
  ~Folder() { fs::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

std::string error_of(const std::string& text, const std::string& file) {
  try {
    parse_scene(text, file);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

const char* kCameras = "# COLMAP\n1 OPENCV_FISHEYE 612 512 165.1 164.9 306.2 255.8 -0.012 0.004 -0.0015 0.0002\n"
                       "2 THIN_PRISM_FISHEYE 612 512 165.1 164.9 306.2 255.8 -0.012 0.004 0.0008 -0.0006 "
                       "-0.0015 0.0002 0.0009 -0.0004\n";

}  // namespace

TEST_CASE("calibration = a COLMAP file: the same lens as the importer; the description carries the text",
          "[scene][camera][calibration]") {
  Folder f;
  f.write("cams/cameras.txt", kCameras);
  const std::string scene_file = (f.path / "scene.toml").string();
  const auto s = parse_scene(kHead + R"([camera]
calibration = "cams/cameras.txt"
calibration_format = "colmap"
calibration_camera = 2
heading_deg = 30
)",
                             scene_file);
  CHECK(s.camera.lens.model == "thin_prism_fisheye");
  // COLMAP's cx = 306.2 is skypol's 305.7.
  CHECK(*s.camera.lens.cx == Approx(305.7).margin(1e-12));
  REQUIRE(s.camera.calibration);
  CHECK(s.camera.calibration->text == kCameras);
  const auto cam = scene::build_camera(s.camera);
  const Eigen::Vector3d d = Eigen::Vector3d(0.3, -0.2, 0.9).normalized();
  const auto p = cam->lens().project(d);
  REQUIRE(p);

  // The file vanishes: the description still rebuilds the same lens, bit for bit.
  fs::remove(f.path / "cams/cameras.txt");
  const auto again = scene::parse_camera(s.camera.description, "header");
  CHECK(again.lens.model == "thin_prism_fisheye");
  CHECK(*again.lens.fov_deg == *s.camera.lens.fov_deg);
  const auto q = scene::build_camera(again)->lens().project(d);
  REQUIRE(q);
  CHECK(*q == *p);
  CHECK(again.description == s.camera.description);
  CHECK(again.heading_deg == 30);
}

TEST_CASE("an OCamCalib path keeps the file's text, so the description survives the file", "[scene][camera][calibration]") {
  Folder f;
  std::ifstream in(fs::path(SKYPOL_SOURCE_DIR) / "tests/camera/data/ocam_calib_results.txt");
  std::stringstream text;
  text << in.rdbuf();
  f.write("calib_results.txt", text.str());
  const std::string scene_file = (f.path / "scene.toml").string();
  for (const std::string& keys : {std::string("model = \"ocam\"\nocamcalib_path = \"calib_results.txt\"\n"),
                                 std::string("calibration = \"calib_results.txt\"\ncalibration_format = \"ocamcalib\"\n")}) {
    INFO(keys);
    f.write("calib_results.txt", text.str());
    const auto s = parse_scene(kHead + "[camera]\n" + keys, scene_file);
    const Eigen::Vector2d px(700.25, 400.5);
    const auto r = scene::build_camera(s.camera)->lens().ray(px);
    REQUIRE(r);
    fs::remove(f.path / "calib_results.txt");
    const auto again = scene::parse_camera(s.camera.description, "header");
    const auto r2 = scene::build_camera(again)->lens().ray(px);
    REQUIRE(r2);
    CHECK(*r2 == *r);
  }
}

TEST_CASE("calibration errors are located at the key, with the calibration file's line", "[scene][camera][calibration]") {
  Folder f;
  const std::string scene_file = f.write("scene.toml", "");
  auto cam = [&](const std::string& keys) { return error_of(kHead + "[camera]\n" + keys, scene_file); };
  CHECK_THAT(cam("calibration = \"nope.txt\"\ncalibration_format = \"colmap\"\n"),
             Catch::Contains("camera.calibration") && Catch::Contains("no such file") && Catch::Contains("nope.txt"));
  f.write("c.txt", "# x\n1 FOV 640 480 300 320 240 0.9\n");
  CHECK_THAT(cam("calibration = \"c.txt\"\ncalibration_format = \"colmap\"\n"),
             Catch::Contains("scene.toml:9") && Catch::Contains("camera.calibration") && Catch::Contains("c.txt:2: COLMAP camera model \"FOV\""));
  f.write("c.txt", "1 RADIAL_FISHEYE 640 480 300 320 240 0.1\n");
  CHECK_THAT(cam("calibration = \"c.txt\"\ncalibration_format = \"colmap\"\n"),
             Catch::Contains("c.txt:1: COLMAP RADIAL_FISHEYE needs 5 parameters"));
  f.write("c.txt", "1 RADIAL_FISHEYE 640 480 300 320 240 0.1 x2\n");
  CHECK_THAT(cam("calibration = \"c.txt\"\ncalibration_format = \"colmap\"\n"), Catch::Contains("\"x2\" is not a number"));
  CHECK_THAT(cam("calibration = \"c.txt\"\n"), Catch::Contains("camera.calibration") && Catch::Contains("needs calibration_format"));
  CHECK_THAT(cam("calibration = \"c.txt\"\ncalibration_format = \"matlab\"\n"),
             Catch::Contains("camera.calibration_format") && Catch::Contains("ocamcalib"));
  f.write("c.txt", "1 RADIAL_FISHEYE 640 480 300 320 240 0.1 0.01\n");
  CHECK_THAT(cam("calibration = \"c.txt\"\ncalibration_format = \"colmap\"\nfx = 300\n"),
             Catch::Contains("camera.fx") && Catch::Contains("not with a calibration"));
  CHECK_THAT(cam("calibration = \"c.txt\"\ncalibration_format = \"colmap\"\ncalibration_camera = 1.5\n"),
             Catch::Contains("camera.calibration_camera") && Catch::Contains("expected a camera id"));
  // OCamCalib and Kalibr files: their own line numbers too.
  f.write("o.txt", "#pol\n5 -260.87 0 1.2778e-03 0 1.2556e-09\n#inv\n2 417.4 291.4\n#centre\n511.3 6l2.8\n#affine\n1 0 0\n#size\n1024 1224\n");
  CHECK_THAT(cam("calibration = \"o.txt\"\ncalibration_format = \"ocamcalib\"\n"),
             Catch::Contains("camera.calibration") && Catch::Contains("o.txt:6: centre \"xc yc\" (row, column): expected 2 numbers"));
  f.write("k.yaml", "cam0:\n  camera_model: ds\n  intrinsics: [0.1, 0.5, 300, 300, 320]\n  resolution: [640, 480]\n");
  CHECK_THAT(cam("calibration = \"k.yaml\"\ncalibration_format = \"kalibr\"\n"),
             Catch::Contains("k.yaml:3: cam0.intrinsics: camera_model ds needs 6"));
  // The text travels in a TOML string, so it must be UTF-8 (a Latin-1 "°" in a comment is not).
  f.write("c.txt", "# 185\xb0 lens\n1 RADIAL_FISHEYE 640 480 300 320 240 0.1 0.01\n");
  CHECK_THAT(cam("calibration = \"c.txt\"\ncalibration_format = \"colmap\"\n"),
             Catch::Contains("camera.calibration") && Catch::Contains("not UTF-8 text"));
  f.write("c.txt", "# 185\xc2\xb0 lens\n1 RADIAL_FISHEYE 640 480 300 320 240 0.1 0.01\n");
  CHECK_NOTHROW(parse_scene(kHead + "[camera]\ncalibration = \"c.txt\"\ncalibration_format = \"colmap\"\n", scene_file));
  // fov_deg overrides the fitted field of view and is checked by the lens.
  const auto s = parse_scene(kHead + "[camera]\ncalibration = \"c.txt\"\ncalibration_format = \"colmap\"\nfov_deg = 150\n", scene_file);
  CHECK(*s.camera.lens.fov_deg == 150);
}

TEST_CASE("every example file in scenes/calibrations loads as docs/scenes.md shows it", "[scene][camera][calibration]") {
  const fs::path dir = fs::path(SKYPOL_SOURCE_DIR) / "scenes";
  struct Example {
    std::string keys, model;
  };
  const std::vector<Example> examples = {
      {"calibration = \"calibrations/cameras.txt\"\ncalibration_format = \"colmap\"\ncalibration_camera = 1\n", "kannala_brandt"},
      {"calibration = \"calibrations/cameras.txt\"\ncalibration_format = \"colmap\"\ncalibration_camera = 2\n", "thin_prism_fisheye"},
      {"calibration = \"calibrations/fisheye.yaml\"\ncalibration_format = \"opencv\"\n", "kannala_brandt"},
      {"calibration = \"calibrations/omnidir.yaml\"\ncalibration_format = \"opencv\"\nfov_deg = 200\n", "mei"},
      {"calibration = \"calibrations/camchain.yaml\"\ncalibration_format = \"kalibr\"\ncalibration_camera = \"cam0\"\n", "double_sphere"},
      {"calibration = \"calibrations/camchain.yaml\"\ncalibration_format = \"kalibr\"\ncalibration_camera = \"cam1\"\n", "eucm"},
      {"calibration = \"calibrations/basalt_calibration.json\"\ncalibration_format = \"basalt\"\ncalibration_camera = 0\n", "kannala_brandt"},
      {"calibration = \"calibrations/calib_results.txt\"\ncalibration_format = \"ocamcalib\"\n", "ocam"},
  };
  for (const Example& e : examples) {
    INFO(e.keys);
    const auto s = parse_scene(kHead + "[camera]\n" + e.keys, (dir / "example.toml").string());
    CHECK(s.camera.lens.model == e.model);
    CHECK(scene::build_camera(s.camera)->lens().name() == e.model);
  }
}
