// make_lens: every model from a LensSpec, and bad input named by its field.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "camera/colmap_import.h"
#include "camera/lens_factory.h"
#include "sky/units.h"

using namespace skypol::camera;
using skypol::kRadPerDeg;

namespace {

LensSpec fujinon_on_imx250() {
  LensSpec s;
  s.model = "equidistant";
  s.width = 2448;
  s.height = 2048;
  s.focal_mm = 1.8;
  s.pitch_um = 3.45;
  s.fov_deg = 185;
  return s;
}
}  // namespace

TEST_CASE("make_lens builds the 185° fisheye from mm and µm", "[factory]") {
  const auto lens = make_lens(fujinon_on_imx250());
  CHECK(lens->name() == "equidistant");
  CHECK(lens->intrinsics().fx == Approx(1.8 / 3.45e-3));
  CHECK(lens->intrinsics().cx == 1223.5);
  CHECK(lens->max_field_angle() == Approx(92.5 * kRadPerDeg));
  LensSpec b = fujinon_on_imx250();
  b.binning = 2;
  const auto lb = make_lens(b);
  CHECK(lb->intrinsics().width == 1224);
  CHECK(lb->intrinsics().fx == Approx(1.8 / 3.45e-3 / 2));
}

TEST_CASE("make_lens builds every model", "[factory]") {
  LensSpec s = fujinon_on_imx250();
  s.model = "kannala_brandt";
  s.coefficients = {0.01, -0.002, 0, 0};
  CHECK(make_lens(s)->name() == "kannala_brandt");
  s.model = "double_sphere";
  s.coefficients = {-0.2, 0.6};
  CHECK(make_lens(s)->name() == "double_sphere");
  s.coefficients.clear();
  s.model = "tabulated";
  s.focal_mm.reset();
  s.fov_deg = 180;  // cut the table at 90°
  for (int d = 10; d <= 90; d += 10) s.table.emplace_back(d, 1.8 * d * kRadPerDeg);
  s.table.emplace_back(95, 1.8 * 95 * kRadPerDeg);
  const auto t = make_lens(s);
  CHECK(t->name() == "tabulated");
  CHECK(t->max_field_angle() == Approx(90 * kRadPerDeg));
  CHECK(t->project({1, 0, 0})->x() == Approx(1223.5 + 1.8 / 3.45e-3 * std::numbers::pi / 2));
  LensSpec o;
  o.model = "ocam";
  o.ocamcalib_path = std::string(SKYPOL_SOURCE_DIR) + "/tests/camera/data/ocam_calib_results.txt";
  o.fov_deg = 185;
  CHECK(make_lens(o)->intrinsics().width == 1224);
}

TEST_CASE("make_lens names the bad field", "[factory]") {
  LensSpec s = fujinon_on_imx250();
  s.focal_mm = -1.8;
  CHECK_THROWS_WITH(make_lens(s), "focal_mm must be > 0");
  s = fujinon_on_imx250();
  s.pitch_um = 0;
  CHECK_THROWS_WITH(make_lens(s), "pitch_um must be > 0");
  s = fujinon_on_imx250();
  s.cx = 3000;
  CHECK_THROWS_WITH(make_lens(s), "principal point off the sensor (cx = 3000, width = 2448)");
  s = fujinon_on_imx250();
  s.fx = 500;
  CHECK_THROWS_WITH(make_lens(s), Catch::Contains("not both"));
  s = fujinon_on_imx250();
  s.fov_deg.reset();
  CHECK_THROWS_WITH(make_lens(s), "fov_deg is required for model equidistant");
  s = fujinon_on_imx250();
  s.model = "fish-eye";
  CHECK_THROWS_WITH(make_lens(s), Catch::Contains("unknown lens model \"fish-eye\"") &&
                                      Catch::Contains("kannala_brandt") && Catch::Contains("tabulated"));
  s = fujinon_on_imx250();
  s.coefficients = {0.1};
  CHECK_THROWS_WITH(make_lens(s), "coefficients: not used by model equidistant");
  s = fujinon_on_imx250();
  s.model = "kannala_brandt";
  s.coefficients = {0.1, 0.2};
  CHECK_THROWS_WITH(make_lens(s), Catch::Contains("kannala_brandt needs 4"));
  // θd = θ − aθ³ turns over at 1/√(3a) = 87.3° for a = 1/(3·(87.3°)²).
  const double tt = 87.3 * kRadPerDeg;
  s.coefficients = {-1 / (3 * tt * tt), 0, 0, 0};
  CHECK_THROWS_WITH(make_lens(s),
                    "distortion curve not monotone over the declared field of view (turns over at 87.3°)");
  s.clamp_fov_to_monotone = true;
  CHECK(make_lens(s)->max_field_angle() == Approx(tt).epsilon(1e-9));
  s = fujinon_on_imx250();
  s.binning = 0;
  CHECK_THROWS_WITH(make_lens(s), Catch::Contains("binning"));
  s = fujinon_on_imx250();
  s.model = "perspective";
  CHECK_THROWS_WITH(make_lens(s), Catch::Contains("perspective"));
  LensSpec o;
  o.model = "ocam";
  o.ocamcalib_path = std::string(SKYPOL_SOURCE_DIR) + "/tests/camera/data/ocam_calib_results.txt";
  o.width = 2448;
  CHECK_THROWS_WITH(make_lens(o), "width 2448 differs from the calibration's 1224");
}

TEST_CASE("COLMAP OPENCV_FISHEYE line: same pixels as COLMAP after the 0.5 px centre shift", "[factory]") {
  // Equidistant-like 185° lens in COLMAP's convention: centre of the 2448×2048 sensor at (1224, 1024).
  const LensSpec s = lens_spec_from_colmap("1 OPENCV_FISHEYE 2448 2048 521.739 521.739 1224 1024 0.01 -0.002 0 0");
  CHECK(s.model == "kannala_brandt");
  CHECK(*s.cx == 1223.5);
  CHECK(*s.cy == 1023.5);
  CHECK(s.coefficients == std::vector<double>{0.01, -0.002, 0, 0});
  const auto lens = make_lens(s);
  // COLMAP's pixel of the direction 60° off-axis towards +x: (cx + f·θd(θ), cy) in its own
  // convention, i.e. 0.5 px less in ours.
  const double t = 60 * kRadPerDeg, td = t * (1 + 0.01 * t * t - 0.002 * std::pow(t, 4));
  const auto p = lens->project({std::sin(t), 0, std::cos(t)});
  REQUIRE(p);
  CHECK(p->x() == Approx(1224 + 521.739 * td - 0.5).epsilon(1e-14));
  CHECK(p->y() == Approx(1023.5));
  // COLMAP knows no field of view; the corners (r = |(1224, 1024)|/f = 3.06) lie beyond what
  // this polynomial reaches at 180° (θd(π) = π(1 + 0.01π² − 0.002π⁴) = 2.84), so fov_deg is the
  // whole 360° and the corner pixels are masked. A scene overrides fov_deg with the lens' 185°.
  CHECK(*s.fov_deg == Approx(360));
  CHECK_FALSE(lens->ray({0, 0}));
  CHECK(lens->ray({1223.5 + 521.739 * 2.8, 1023.5}));
}

TEST_CASE("COLMAP PINHOLE line and its errors", "[factory]") {
  const LensSpec s = lens_spec_from_colmap("3 SIMPLE_PINHOLE 640 480 500 320 240");
  CHECK(s.model == "perspective");
  CHECK(*s.fy == 500);
  // Farthest corner (−0.5 − 319.5, −0.5 − 239.5) = 400 px → θ = atan(0.8), FOV 77.32°.
  CHECK(*s.fov_deg == Approx(2 * std::atan(0.8) / kRadPerDeg));
  CHECK(make_lens(s)->name() == "perspective");
  CHECK_THROWS_WITH(lens_spec_from_colmap("1 FOV 640 480 300 320 240 0.9"),
                    Catch::Contains("not supported") && Catch::Contains("OPENCV_FISHEYE"));
  CHECK_THROWS_WITH(lens_spec_from_colmap("1 PINHOLE 640 480 500 500 320"),
                    Catch::Contains("needs 4 parameters (fx, fy, cx, cy), got 3"));
  CHECK_THROWS_WITH(lens_spec_from_colmap("1 PINHOLE 640 480 500 abc 320 240"),
                    Catch::Contains("\"abc\" is not a number"));
}
