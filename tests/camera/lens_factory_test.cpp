// make_lens: every model from a LensSpec, and bad input named by its field.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>

#include "camera/lens_factory.h"

using namespace skypol::camera;

namespace {
constexpr double kDeg = std::numbers::pi / 180;

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
  CHECK(lens->max_field_angle() == Approx(92.5 * kDeg));
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
  for (int d = 10; d <= 90; d += 10) s.table.emplace_back(d, 1.8 * d * kDeg);
  s.table.emplace_back(95, 1.8 * 95 * kDeg);
  const auto t = make_lens(s);
  CHECK(t->name() == "tabulated");
  CHECK(t->max_field_angle() == Approx(90 * kDeg));
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
  const double tt = 87.3 * kDeg;
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
