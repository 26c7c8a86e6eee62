// The calibration importers give the pixels of the source tool's own formulas (written out here
// from COLMAP's models.h, OpenCV's fisheye.cpp and omnidir.cpp, Usenko et al. 2018 and Khomutenko
// et al. 2016, independently of camera/), round-trip pixel → ray → pixel, and report bad files
// at their line.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <numbers>

#include "camera/calibration_import.h"
#include "camera/eucm.h"
#include "camera/intrinsics.h"
#include "camera/lens_factory.h"
#include "camera/mei_lens.h"
#include "camera/thin_prism_fisheye.h"
#include "camera_test_util.h"
#include "sky/units.h"

using namespace skypol::camera;
using skypol::testing::dir;
using skypol::kRadPerDeg;

namespace {

// A source tool's projection of a camera-frame point (x, y, z) to ITS pixel coordinates.
using Oracle = std::function<Eigen::Vector2d(double x, double y, double z)>;

std::shared_ptr<const Lens> import(const std::string& format, const std::string& text, const std::string& camera = "") {
  return make_lens(lens_spec_from_calibration({format, text, "test." + format, camera}));
}

// Directions up to theta_max_deg at 24 azimuths: the lens's pixel equals the oracle's plus `shift`.
double worst_against(const Lens& lens, const Oracle& oracle, double theta_max_deg, double shift) {
  double worst = 0;
  for (double t = 0; t <= theta_max_deg + 1e-9; t += theta_max_deg / 20)
    for (int j = 0; j < 24; ++j) {
      const Eigen::Vector3d d = dir(t * kRadPerDeg, j * 15 * kRadPerDeg + 0.1);
      const auto p = lens.project(d);
      REQUIRE(p);
      const Eigen::Vector2d q = oracle(d.x(), d.y(), d.z()) + Eigen::Vector2d(shift, shift);
      worst = std::max(worst, (*p - q).norm());
    }
  return worst;
}

// Pixel → ray → pixel over a grid of the sensor's pixels that see something.
double worst_round_trip(const Lens& lens) {
  const Intrinsics& k = lens.intrinsics();
  double worst = 0;
  int seen = 0;
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      const Eigen::Vector2d px(i * (k.width - 1) / 40.0, j * (k.height - 1) / 40.0);
      const auto d = lens.ray(px);
      if (!d) continue;
      ++seen;
      const auto back = lens.project(*d);
      REQUIRE(back);
      worst = std::max(worst, (*back - px).norm());
    }
  CHECK(seen > 300);  // most of the 41×41 grid
  return worst;
}

// COLMAP: the normalized point, its equidistant "fisheye" point, then each model's Distortion().
Eigen::Vector2d colmap_fisheye(double x, double y, double z) {
  const double u = x / z, v = y / z, r = std::hypot(u, v);
  if (r == 0) return {0, 0};
  const double th = std::atan(r);
  return {u * th / r, v * th / r};
}

const char* kColmapCameras = R"(# Camera list with one line of data per camera:
#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]
# Number of cameras: 4
1 SIMPLE_RADIAL_FISHEYE 1224 1024 330.5 612.25 511.75 -0.021
2 RADIAL_FISHEYE 1224 1024 331.0 611.9 512.3 -0.018 0.0011
3 OPENCV_FISHEYE 1224 1024 330.2 329.7 612.4 511.6 -0.012 0.004 -0.0015 0.0002
4 THIN_PRISM_FISHEYE 1224 1024 330.2 329.7 612.4 511.6 -0.012 0.004 0.0008 -0.0006 -0.0015 0.0002 0.0009 -0.0004
)";

}  // namespace

TEST_CASE("COLMAP cameras.txt: the four fisheye models give COLMAP's pixels minus 0.5", "[calibration]") {
  struct Case {
    std::string id;
    Oracle oracle;
  };
  const std::vector<Case> cases = {
      {"1",
       [](double x, double y, double z) {
         const Eigen::Vector2d p = colmap_fisheye(x, y, z);
         const double k = -0.021, radial = k * p.squaredNorm();
         return Eigen::Vector2d(330.5 * (p.x() + p.x() * radial) + 612.25, 330.5 * (p.y() + p.y() * radial) + 511.75);
       }},
      {"2",
       [](double x, double y, double z) {
         const Eigen::Vector2d p = colmap_fisheye(x, y, z);
         const double t2 = p.squaredNorm(), radial = -0.018 * t2 + 0.0011 * t2 * t2;
         return Eigen::Vector2d(331.0 * p.x() * (1 + radial) + 611.9, 331.0 * p.y() * (1 + radial) + 512.3);
       }},
      {"3",
       [](double x, double y, double z) {
         const Eigen::Vector2d p = colmap_fisheye(x, y, z);
         const double t2 = p.squaredNorm();
         const double radial = -0.012 * t2 + 0.004 * t2 * t2 - 0.0015 * t2 * t2 * t2 + 0.0002 * t2 * t2 * t2 * t2;
         return Eigen::Vector2d(330.2 * p.x() * (1 + radial) + 612.4, 329.7 * p.y() * (1 + radial) + 511.6);
       }},
      {"4",
       [](double x, double y, double z) {
         const Eigen::Vector2d p = colmap_fisheye(x, y, z);
         const double k1 = -0.012, k2 = 0.004, p1 = 0.0008, p2 = -0.0006, k3 = -0.0015, k4 = 0.0002, sx1 = 0.0009,
                      sy1 = -0.0004;
         const double u = p.x(), v = p.y(), u2 = u * u, v2 = v * v, uv = u * v, r2 = u2 + v2;
         const double radial = k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2 + k4 * r2 * r2 * r2 * r2;
         const double du = u * radial + 2 * p1 * uv + p2 * (r2 + 2 * u2) + sx1 * r2;
         const double dv = v * radial + 2 * p2 * uv + p1 * (r2 + 2 * v2) + sy1 * r2;
         return Eigen::Vector2d(330.2 * (u + du) + 612.4, 329.7 * (v + dv) + 511.6);
       }},
  };
  for (const Case& c : cases) {
    INFO("CAMERA_ID " << c.id);
    const auto lens = import("colmap", kColmapCameras, c.id);
    // COLMAP projects only z > 0: compare up to 85°.
    const double worst = worst_against(*lens, c.oracle, 85, -0.5);
    WARN("COLMAP camera " << c.id << " (" << lens->name() << "): worst difference " << worst << " px");
    CHECK(worst < 1e-9);
    CHECK(worst_round_trip(*lens) < 1e-6);
  }
  CHECK(import("colmap", kColmapCameras, "4")->name() == "thin_prism_fisheye");
  CHECK(import("colmap", kColmapCameras, "1")->name() == "kannala_brandt");
}

TEST_CASE("COLMAP cameras.txt: located errors", "[calibration]") {
  auto error = [](const std::string& text, const std::string& camera = "") {
    try {
      (void)lens_spec_from_calibration({"colmap", text, "cams.txt", camera});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(error(kColmapCameras), Catch::Contains("cams.txt: 4 cameras (1, 2, 3, 4); choose one with calibration_camera"));
  CHECK_THAT(error(kColmapCameras, "7"), Catch::Contains("no camera with CAMERA_ID 7 (the file has 1, 2, 3, 4)"));
  CHECK_THAT(error("# c\n\n1 FOV 640 480 300 320 240 0.9\n"),
             Catch::Contains("cams.txt:3: COLMAP camera model \"FOV\" is not supported") &&
                 Catch::Contains("THIN_PRISM_FISHEYE"));
  CHECK_THAT(error("1 THIN_PRISM_FISHEYE 640 480 300 300 320 240 0 0 0 0 0 0 0\n"),
             Catch::Contains("cams.txt:1: COLMAP THIN_PRISM_FISHEYE needs 12 parameters") && Catch::Contains("got 11"));
  CHECK_THAT(error("#\n1 RADIAL_FISHEYE 640 480 300 320 240 0.0x1 0\n"),
             Catch::Contains("cams.txt:2: COLMAP camera line: parameter \"0.0x1\" is not a number"));
  CHECK_THAT(error("# only comments\n"), Catch::Contains("cams.txt: no camera lines"));
}

TEST_CASE("thin prism fisheye: folds are refused, the field of view is fitted to the sensor", "[calibration]") {
  const LensSpec s = lens_spec_from_calibration({"colmap", kColmapCameras, "c", "4"});
  // No field of view in COLMAP: the farthest corner of 1224×1024 at f ≈ 330 px, θ ≈ r ≈ 2.4 rad.
  REQUIRE(s.fov_deg);
  const auto lens = make_lens(s);
  double widest = 0;
  for (double u : {-0.5, 1223.5})
    for (double v : {-0.5, 1023.5}) {
      const auto corner = lens->ray({u, v});
      REQUIRE(corner);
      widest = std::max(widest, 2 * std::acos(corner->z()) / kRadPerDeg);
    }
  CHECK(widest == Approx(*s.fov_deg).epsilon(1e-9));
  // A strong negative k1 folds the map: θd = θ(1 − 0.3θ²) turns over at θ = 1/√0.9 = 60.4°.
  Intrinsics k = skypol::testing::imx250();
  CHECK_THROWS_WITH(ThinPrismFisheyeLens(k, {-0.3, 0, 0, 0, 0, 0, 0, 0}, 90 * kRadPerDeg),
                    Catch::Contains("not one-to-one") && Catch::Contains("60."));
  CHECK_NOTHROW(ThinPrismFisheyeLens(k, {-0.3, 0, 0, 0, 0, 0, 0, 0}, 60 * kRadPerDeg));
}

namespace {

// cv::fisheye::projectPoints (fisheye.cpp): θ = atan(r), θd polynomial, x' = (θd/r)·x.
Eigen::Vector2d opencv_fisheye(double x, double y, double z, const double* K, const double* D) {
  const double a = x / z, b = y / z, r = std::hypot(a, b);
  const double th = std::atan(r), t2 = th * th;
  const double thd = th * (1 + D[0] * t2 + D[1] * t2 * t2 + D[2] * t2 * t2 * t2 + D[3] * t2 * t2 * t2 * t2);
  const double s = r > 0 ? thd / r : 1;
  return {K[0] * a * s + K[2], K[4] * b * s + K[5]};
}

// cv::omnidir::projectPoints (omnidir.cpp): unit sphere, shift by ξ, radial-tangential, K with skew.
Eigen::Vector2d opencv_omnidir(double x, double y, double z, const double* K, const double* D, double xi) {
  const double n = std::sqrt(x * x + y * y + z * z);
  const double xs = x / n, ys = y / n, zs = z / n;
  const double xu = xs / (zs + xi), yu = ys / (zs + xi);
  const double r2 = xu * xu + yu * yu, r4 = r2 * r2;
  const double xd = xu * (1 + D[0] * r2 + D[1] * r4) + 2 * D[2] * xu * yu + D[3] * (r2 + 2 * xu * xu);
  const double yd = yu * (1 + D[0] * r2 + D[1] * r4) + D[2] * (r2 + 2 * yu * yu) + 2 * D[3] * xu * yu;
  return {K[0] * xd + K[1] * yd + K[2], K[4] * yd + K[5]};
}

const double kFisheyeK[9] = {330.2, 0, 612.4, 0, 329.7, 511.6, 0, 0, 1};
const double kFisheyeD[4] = {-0.012, 0.004, -0.0015, 0.0002};
const double kOmniK[9] = {560.1, 0.35, 611.8, 0, 559.4, 512.7, 0, 0, 1};
const double kOmniD[4] = {-0.21, 0.045, 0.0007, -0.0004};
const double kOmniXi = 1.62;

const char* kOpenCvFisheyeYaml = R"(%YAML:1.0
---
image_width: 1224
image_height: 1024
K: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 330.2, 0., 612.4, 0., 329.7, 511.6, 0., 0., 1. ]
D: !!opencv-matrix
   rows: 4
   cols: 1
   dt: d
   data: [ -0.012, 0.004, -0.0015, 0.0002 ]
)";

const char* kOpenCvOmniYaml = R"(%YAML:1.0
---
image_size: [ 1224, 1024 ]
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 560.1, 0.35, 611.8, 0., 559.4, 512.7, 0., 0., 1. ]
D: !!opencv-matrix
   rows: 1
   cols: 4
   dt: d
   data: [ -0.21, 0.045, 0.0007, -0.0004 ]
xi: !!opencv-matrix
   rows: 1
   cols: 1
   dt: d
   data: [ 1.62 ]
)";

const char* kOpenCvOmniJson = R"({
    "image_width": 1224,
    "image_height": 1024,
    "K": {"type_id": "opencv-matrix", "rows": 3, "cols": 3, "dt": "d",
          "data": [560.1, 0.35, 611.8, 0.0, 559.4, 512.7, 0.0, 0.0, 1.0]},
    "D": {"type_id": "opencv-matrix", "rows": 1, "cols": 4, "dt": "d",
          "data": [-0.21, 0.045, 0.0007, -0.0004]},
    "xi": 1.62
}
)";

}  // namespace

TEST_CASE("OpenCV FileStorage: cv::fisheye and cv::omnidir give OpenCV's pixels", "[calibration]") {
  const auto fe = import("opencv", kOpenCvFisheyeYaml);
  CHECK(fe->name() == "kannala_brandt");
  const double wf = worst_against(*fe, [](double x, double y, double z) { return opencv_fisheye(x, y, z, kFisheyeK, kFisheyeD); }, 85, 0);
  WARN("cv::fisheye: worst difference " << wf << " px");
  CHECK(wf < 1e-9);
  CHECK(worst_round_trip(*fe) < 1e-6);

  for (const char* text : {kOpenCvOmniYaml, kOpenCvOmniJson}) {
    const auto om = import("opencv", text);
    CHECK(om->name() == "mei");
    // ξ = 1.62 images past 180°: compare up to 110° (the oracle has no z > 0 limit).
    const double wo = worst_against(*om, [](double x, double y, double z) { return opencv_omnidir(x, y, z, kOmniK, kOmniD, kOmniXi); }, 110, 0);
    WARN("cv::omnidir: worst difference " << wo << " px");
    CHECK(wo < 1e-9);
    CHECK(worst_round_trip(*om) < 1e-6);
    CHECK(om->max_field_angle() > 100 * kRadPerDeg);
  }
}

TEST_CASE("OpenCV FileStorage: located errors", "[calibration]") {
  auto error = [](const std::string& text) {
    try {
      (void)lens_spec_from_calibration({"opencv", text, "cal.yaml", ""});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string t = kOpenCvFisheyeYaml;
  CHECK_THAT(error(t.substr(0, t.find("D: !!"))), Catch::Contains("cal.yaml:3: missing the distortion coefficients"));
  std::string bad = t;
  bad.replace(bad.find("0.004,"), 6, "0.0o4,");
  CHECK_THAT(error(bad), Catch::Contains("cal.yaml:14: D.data: \"0.0o4\" is not a number"));
  bad = t;
  bad.replace(bad.find("rows: 4"), 7, "rows: 5");
  CHECK_THAT(error(bad), Catch::Contains("cal.yaml:14: D.data: 4 numbers for a 5×1 matrix"));
  bad = t;
  bad.replace(bad.find("rows: 4"), 7, "rows: 5");
  bad.replace(bad.find("0.0002 ]"), 8, "0.0002, 0.1 ]");
  CHECK_THAT(error(bad), Catch::Contains("cal.yaml:10: D has 5 coefficients: that is cv::calibrateCamera's pinhole model"));
  CHECK_THAT(error("%YAML:1.0\nK: [1, 2\n"), Catch::Contains("cal.yaml:3: YAML syntax error"));
  bad = t;
  bad.replace(bad.find("image_width: 1224\n"), 18, "");
  CHECK_THAT(error(bad), Catch::Contains("missing the image size"));
}

namespace {

// Usenko et al. 2018 eq. 40-41 (double sphere), Khomutenko et al. 2016 eq. (EUCM), Mei 2007.
Eigen::Vector2d ds(double x, double y, double z, double xi, double a, double fx, double fy, double cx, double cy) {
  const double d1 = std::sqrt(x * x + y * y + z * z);
  const double d2 = std::sqrt(x * x + y * y + (xi * d1 + z) * (xi * d1 + z));
  const double den = a * d2 + (1 - a) * (xi * d1 + z);
  return {fx * x / den + cx, fy * y / den + cy};
}
Eigen::Vector2d eucm(double x, double y, double z, double a, double b, double fx, double fy, double cx, double cy) {
  const double d = std::sqrt(b * (x * x + y * y) + z * z);
  const double den = a * d + (1 - a) * z;
  return {fx * x / den + cx, fy * y / den + cy};
}

const char* kCamchain = R"(cam0:
  camera_model: ds
  intrinsics: [-0.18, 0.59, 351.2, 350.8, 611.0, 512.9]
  distortion_model: none
  distortion_coeffs: []
  resolution: [1224, 1024]
  rostopic: /cam0/image_raw
cam1:
  camera_model: eucm
  intrinsics: [0.61, 1.08, 352.4, 352.0, 612.2, 511.1]
  distortion_model: none
  distortion_coeffs: []
  resolution: [1224, 1024]
cam2:
  camera_model: pinhole
  intrinsics: [330.2, 329.7, 612.4, 511.6]
  distortion_model: equidistant
  distortion_coeffs: [-0.012, 0.004, -0.0015, 0.0002]
  resolution: [1224, 1024]
cam3:
  camera_model: omni
  intrinsics: [1.62, 560.1, 559.4, 611.8, 512.7]
  distortion_model: radtan
  distortion_coeffs: [-0.21, 0.045, 0.0007, -0.0004]
  resolution: [1224, 1024]
)";

}  // namespace

TEST_CASE("Kalibr camchain: ds, eucm, pinhole-equidistant and omni-radtan give the models' pixels", "[calibration]") {
  const double k0[9] = {330.2, 0, 612.4, 0, 329.7, 511.6, 0, 0, 1};
  const double kOmni0[9] = {560.1, 0, 611.8, 0, 559.4, 512.7, 0, 0, 1};
  struct Case {
    std::string cam, model;
    Oracle oracle;
    double up_to_deg;
  };
  const std::vector<Case> cases = {
      {"cam0", "double_sphere", [](double x, double y, double z) { return ds(x, y, z, -0.18, 0.59, 351.2, 350.8, 611.0, 512.9); }, 95},
      {"cam1", "eucm", [](double x, double y, double z) { return eucm(x, y, z, 0.61, 1.08, 352.4, 352.0, 612.2, 511.1); }, 95},
      {"cam2", "kannala_brandt", [&](double x, double y, double z) { return opencv_fisheye(x, y, z, k0, kFisheyeD); }, 85},
      {"cam3", "mei", [&](double x, double y, double z) { return opencv_omnidir(x, y, z, kOmni0, kOmniD, kOmniXi); }, 110},
  };
  for (const Case& c : cases) {
    INFO(c.cam);
    const auto lens = import("kalibr", kCamchain, c.cam);
    CHECK(lens->name() == c.model);
    const double worst = worst_against(*lens, c.oracle, c.up_to_deg, 0);
    WARN("Kalibr " << c.cam << " (" << c.model << "): worst difference " << worst << " px");
    CHECK(worst < 1e-9);
    CHECK(worst_round_trip(*lens) < 1e-6);
  }
}

TEST_CASE("Kalibr camchain and basalt: located errors", "[calibration]") {
  auto error = [](const std::string& format, const std::string& text, const std::string& cam = "") {
    try {
      (void)lens_spec_from_calibration({format, text, "chain.yaml", cam});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(error("kalibr", kCamchain), Catch::Contains("chain.yaml:1: 4 cameras (cam0, cam1, cam2, cam3)"));
  CHECK_THAT(error("kalibr", kCamchain, "cam9"), Catch::Contains("no camera \"cam9\""));
  std::string bad = kCamchain;
  bad.replace(bad.find("camera_model: eucm"), 18, "camera_model: mei ");
  CHECK_THAT(error("kalibr", bad, "cam1"), Catch::Contains("chain.yaml:9: cam1.camera_model \"mei\" is not supported"));
  bad = kCamchain;
  bad.replace(bad.find("[0.61, 1.08, "), 13, "[0.61, ");
  CHECK_THAT(error("kalibr", bad, "cam1"), Catch::Contains("chain.yaml:10: cam1.intrinsics: camera_model eucm needs 6") &&
                                                 Catch::Contains("got 5"));
  bad = kCamchain;
  bad.replace(bad.find("0.61,"), 5, "0.6l,");
  CHECK_THAT(error("kalibr", bad, "cam1"), Catch::Contains("chain.yaml:10: cam1.intrinsics: \"0.6l\" is not a number"));
  bad = kCamchain;
  bad.replace(bad.find("distortion_model: equidistant"), 29, "distortion_model: radtan     ");
  CHECK_THAT(error("kalibr", bad, "cam2"), Catch::Contains("chain.yaml:17: cam2: camera_model pinhole with distortion_model radtan is not supported"));
  CHECK_THAT(error("basalt", R"({"value0": {"intrinsics": [{"camera_type": "fov", "intrinsics": {}}], "resolution": [[640, 480]]}})"),
             Catch::Contains("camera_type \"fov\" is not supported"));
}

TEST_CASE("basalt calibration.json: ds and kb4 by index", "[calibration]") {
  const std::string json = R"({
  "value0": {
    "intrinsics": [
      {"camera_type": "ds",
       "intrinsics": {"fx": 351.2, "fy": 350.8, "cx": 611.0, "cy": 512.9, "xi": -0.18, "alpha": 0.59}},
      {"camera_type": "kb4",
       "intrinsics": {"fx": 330.2, "fy": 329.7, "cx": 612.4, "cy": 511.6,
                      "k1": -0.012, "k2": 0.004, "k3": -0.0015, "k4": 0.0002}}
    ],
    "resolution": [[1224, 1024], [1224, 1024]]
  }
})";
  const auto l0 = import("basalt", json, "0");
  CHECK(worst_against(*l0, [](double x, double y, double z) { return ds(x, y, z, -0.18, 0.59, 351.2, 350.8, 611.0, 512.9); }, 95, 0) < 1e-9);
  const auto l1 = import("basalt", json, "1");
  CHECK(worst_against(*l1, [](double x, double y, double z) { return opencv_fisheye(x, y, z, kFisheyeK, kFisheyeD); }, 85, 0) < 1e-9);
  CHECK_THROWS_WITH(import("basalt", json), Catch::Contains("2 cameras; choose one with calibration_camera (0..1)"));
}

TEST_CASE("EUCM with beta = 1 is Mei's model with xi = alpha/(1 - alpha), f/(1 - alpha)", "[calibration]") {
  Intrinsics k = skypol::testing::imx250(300);
  const double a = 0.6;
  const EucmLens e(k, a, 1.0, 100 * kRadPerDeg);
  Intrinsics km = k;
  km.fx = km.fy = 300 / (1 - a);
  const MeiLens m(km, 0, a / (1 - a), {0, 0, 0, 0}, 100 * kRadPerDeg);
  for (double t = 0; t <= 100; t += 5)
    for (double phi : {0.2, 1.9, 4.4}) {
      const auto p = e.project(dir(t * kRadPerDeg, phi));
      const auto q = m.project(dir(t * kRadPerDeg, phi));
      REQUIRE(p);
      REQUIRE(q);
      CHECK((*p - *q).norm() < 1e-9);
    }
  CHECK(worst_round_trip(e) < 1e-6);
  // Mei's limit for ξ = 1.5 is acos(−1/1.5) = 131.8°.
  CHECK(MeiLens::valid_angle(1.5) / kRadPerDeg == Approx(131.8103149));
  CHECK_THROWS_WITH(MeiLens(km, 0, 1.5, {0, 0, 0, 0}, 132 * kRadPerDeg), Catch::Contains("exceeds the unified (Mei) model's limit of 131.8°"));
}

TEST_CASE("the new models bin exactly: a binned copy sees every direction at (p + 1/2)/2 - 1/2", "[calibration]") {
  const std::vector<std::shared_ptr<const Lens>> lenses = {
      import("colmap", kColmapCameras, "4"), import("opencv", kOpenCvOmniYaml), import("kalibr", kCamchain, "cam1")};
  for (const auto& lens : lenses) {
    INFO(lens->name());
    const auto b = binned(*lens, 2);
    for (double t : {0.0, 0.4, 1.2, 1.6})
      for (double phi : {0.3, 2.0, 4.0}) {
        const auto p = lens->project(dir(t, phi));
        const auto q = b->project(dir(t, phi));
        REQUIRE(p);
        REQUIRE(q);
        CHECK((*q - ((*p).array() + 0.5).matrix() / 2 + Eigen::Vector2d(0.5, 0.5)).norm() < 1e-9);
      }
    CHECK(worst_round_trip(*b) < 1e-6);
  }
}
