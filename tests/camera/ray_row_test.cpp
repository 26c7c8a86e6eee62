// Lens::ray_row and Camera::ray_row, the renderer's batched ray paths, against ray() pixel by
// pixel, for every model, including the principal point, the edge of the image circle and pixels
// outside it. The closed forms (the ideal mappings, the tabulated lens, double sphere, EUCM,
// OCamCalib) give the same bits as ray(). The models without one (Kannala-Brandt, thin prism,
// Mei) interpolate a table and finish with Newton steps, where ray() iterates to convergence from
// another start: the two agree to 1e-12 rad (both are within ~1e-15 of the true inverse; the
// bound leaves room for the steepest part of a curve), and ray_row's round trip is < 1e-6 px.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "camera/camera.h"
#include "camera/detail/ray_kernels.h"
#include "camera/detail/ray_table.h"
#include "camera/double_sphere.h"
#include "camera/eucm.h"
#include "camera/kannala_brandt.h"
#include "camera/mei_lens.h"
#include "camera/ocam_lens.h"
#include "camera/radial_lens.h"
#include "camera/tabulated_lens.h"
#include "camera/thin_prism_fisheye.h"
#include "camera_test_util.h"
#include "sky/units.h"

using namespace skypol::camera;
using namespace skypol::testing;
using skypol::kRadPerDeg;

namespace {
const std::string kOcamFile = std::string(SKYPOL_SOURCE_DIR) + "/tests/camera/data/ocam_calib_results.txt";

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Named {
  std::string what;
  std::shared_ptr<const Lens> lens;
  bool same_bits = true;  // a closed form shared with ray(); else within kTabulatedRad of it
};

constexpr double kTabulatedRad = 1e-12;

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// The SkyPole camera through cv::omnidir's model (scenes/calibrations/omnidir.yaml's numbers).
std::shared_ptr<const Lens> mei() {
  Intrinsics k = imx250(1480.2);
  k.fy = 1479.6, k.cx = 1223.4, k.cy = 1023.9;
  return std::make_shared<MeiLens>(k, 0.2, 1.8, std::array{-0.02, 0.003, 0.0002, -0.0001}, 92.5 * kRadPerDeg);
}

std::vector<Named> lenses() {
  std::vector<std::pair<double, double>> table;
  for (int d = 5; d <= 90; d += 5) table.emplace_back(d, 2 * 1.8 * std::sin(d * kRadPerDeg / 2));
  table.emplace_back(92.5, 2 * 1.8 * std::sin(92.5 * kRadPerDeg / 2));
  Intrinsics off = imx250();
  off.cx = 1100.25, off.cy = 990.75, off.fy = kF * 1.01;  // principal point off the centre, fx ≠ fy
  return {
      {"equidistant", std::make_shared<RadialLens>(Mapping::equidistant, imx250(), 92.5 * kRadPerDeg)},
      {"equidistant, off-centre, fx != fy", std::make_shared<RadialLens>(Mapping::equidistant, off, 92.5 * kRadPerDeg)},
      {"equisolid", std::make_shared<RadialLens>(Mapping::equisolid, imx250(), 92.5 * kRadPerDeg)},
      {"equisolid 180", std::make_shared<RadialLens>(Mapping::equisolid, imx250(400), 180 * kRadPerDeg)},
      {"stereographic", std::make_shared<RadialLens>(Mapping::stereographic, imx250(), 92.5 * kRadPerDeg)},
      {"orthographic", std::make_shared<RadialLens>(Mapping::orthographic, imx250(900), 90 * kRadPerDeg)},
      {"perspective", std::make_shared<RadialLens>(Mapping::perspective, imx250(700), 60 * kRadPerDeg)},
      {"tabulated", std::make_shared<TabulatedLens>(imx250(1 / 3.45e-3), height_table_from_deg_mm(table))},
      {"double_sphere", std::make_shared<DoubleSphereLens>(imx250(), -0.2, 0.6, 92.5 * kRadPerDeg)},
      {"eucm", std::make_shared<EucmLens>(imx250(), 0.6, 1.1, 92.5 * kRadPerDeg)},
      {"ocam", std::make_shared<OCamLens>(load_ocamcalib(kOcamFile), 92.5 * kRadPerDeg)},
      {"kannala_brandt",
       std::make_shared<KannalaBrandtLens>(imx250(), std::array{0.012, -0.004, 0.0008, -0.00005}, 92.5 * kRadPerDeg), false},
      // θd = θ − aθ³ turns over at 93°, where the field is cut: dθd/dθ → 0 at the edge, so the
      // pixels near it take ray() itself.
      {"kannala_brandt cut at its turning point",
       std::make_shared<KannalaBrandtLens>(imx250(), std::array{-1 / (3 * std::pow(93 * kRadPerDeg, 2)), 0.0, 0.0, 0.0},
                                           95 * kRadPerDeg, KannalaBrandtLens::OnTurnover::clamp_fov),
       false},
      {"thin_prism_fisheye",
       std::make_shared<ThinPrismFisheyeLens>(
           imx250(), std::array{0.0061, -0.0018, 0.00012, -0.00008, 0.00031, -0.00002, 0.00021, -0.00011}, 92.5 * kRadPerDeg),
       false},
      {"mei", mei(), false},
  };
}

// Rows through the principal point, the top and bottom of the image circle and the sensor's edges.
std::vector<int> rows_of(const Lens& lens) {
  const Intrinsics& k = lens.intrinsics();
  std::vector<int> rows = {0, k.height - 1, static_cast<int>(std::floor(k.cy)), static_cast<int>(std::ceil(k.cy))};
  for (int y = 0; y < k.height; y += 37) rows.push_back(y);
  return rows;
}
}  // namespace

TEST_CASE("Lens::ray_row is ray(): bit for bit for the closed forms, to 1e-12 rad for the tabulated inverses",
          "[lens]") {
  for (const auto& [what, lens, exact] : lenses()) {
    INFO(what);
    const std::size_t w = static_cast<std::size_t>(lens->intrinsics().width);
    std::vector<double> dx(w), dy(w), dz(w);
    std::vector<unsigned char> valid(w);
    std::size_t inside = 0, outside = 0, mismatches = 0;
    for (int y : rows_of(*lens)) {
      lens->ray_row(y, 0, w, dx.data(), dy.data(), dz.data(), valid.data());
      for (std::size_t x = 0; x < w; ++x) {
        const auto r = lens->ray(Eigen::Vector2d(static_cast<double>(x), y));
        if (static_cast<bool>(r) != (valid[x] != 0)) {
          ++mismatches;
          continue;
        }
        if (!r) {
          ++outside;
          if (!(dx[x] == 0 && dy[x] == 0 && dz[x] == 1)) ++mismatches;
          continue;
        }
        ++inside;
        const Eigen::Vector3d d(dx[x], dy[x], dz[x]);
        if (exact ? !same_bits(r->x(), dx[x]) || !same_bits(r->y(), dy[x]) || !same_bits(r->z(), dz[x])
                  : !(angle_between(*r, d) <= kTabulatedRad && std::abs(d.norm() - 1) <= 1e-15))
          ++mismatches;
      }
    }
    CHECK(mismatches == 0);
    CHECK(inside > 1000);  // the rows cross the image circle...
    if (what.find("perspective") == std::string::npos) CHECK(outside > 1000);  // ...and leave it
  }
}

TEST_CASE("Lens::ray_row at the principal point and from a non-zero start column", "[lens]") {
  Intrinsics k = imx250();
  k.cx = 1000, k.cy = 900;  // integral: a pixel centre sits on the axis
  const RadialLens lens(Mapping::equisolid, k, 92.5 * kRadPerDeg);
  double dx[5], dy[5], dz[5];
  unsigned char valid[5];
  lens.ray_row(900, 998, 5, dx, dy, dz, valid);
  for (int i = 0; i < 5; ++i) {
    const auto r = lens.ray(Eigen::Vector2d(998 + i, 900));
    REQUIRE(r);
    CHECK(valid[i] == 1);
    CHECK((same_bits(r->x(), dx[i]) && same_bits(r->y(), dy[i]) && same_bits(r->z(), dz[i])));
  }
  CHECK((dx[2] == 0 && dy[2] == 0 && dz[2] == 1));  // the axis itself
}

TEST_CASE("Camera::ray_row is Camera::ray cast to float (bit for bit for the closed forms) under a tilted orientation",
          "[camera]") {
  const Eigen::Matrix3d r =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  for (const auto& [what, lens, exact] : lenses()) {
    INFO(what);
    const Camera cam(lens, r);
    const std::size_t w = static_cast<std::size_t>(cam.width());
    std::vector<float> p[7];
    for (auto& v : p) v.resize(w);
    std::size_t mismatches = 0;
    for (int y : rows_of(*lens)) {
      cam.ray_row(y, 0, w, {p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data(), p[5].data(), p[6].data()});
      for (std::size_t x = 0; x < w; ++x) {
        const auto ray = cam.ray(Eigen::Vector2d(static_cast<double>(x), y));
        const Eigen::Vector3f d = ray ? Eigen::Vector3f(ray->d.cast<float>()) : Eigen::Vector3f::UnitZ();
        const Eigen::Vector3f e = ray ? Eigen::Vector3f(ray->e0.cast<float>()) : Eigen::Vector3f::UnitX();
        const float got[7] = {p[0][x], p[1][x], p[2][x], p[3][x], p[4][x], p[5][x], p[6][x]};
        const float want[7] = {d.x(), d.y(), d.z(), e.x(), e.y(), e.z(), ray ? 1.0f : 0.0f};
        // Where the lens's rays differ from ray() in the last bits of a double, their floats may
        // differ by one float ulp.
        for (int c = 0; c < 7; ++c)
          mismatches += same_bits(got[c], want[c]) || (!exact && std::abs(got[c] - want[c]) <= 1.2e-7f) ? 0 : 1;
      }
    }
    CHECK(mismatches == 0);
  }
}

TEST_CASE("Lens::ray_row's round trip project(ray_row(p)) = p is < 1e-6 px on every pixel of every fifth row", "[lens]") {
  for (const auto& [what, lens, exact] : lenses()) {
    INFO(what);
    const Intrinsics& k = lens->intrinsics();
    const std::size_t w = static_cast<std::size_t>(k.width);
    std::vector<double> dx(w), dy(w), dz(w);
    std::vector<unsigned char> valid(w);
    double worst = 0;
    std::size_t inside = 0, refused = 0;
    std::vector<int> rows = rows_of(*lens);
    for (int y = 1; y < k.height; y += 5) rows.push_back(y);
    for (int y : rows) {
      lens->ray_row(y, 0, w, dx.data(), dy.data(), dz.data(), valid.data());
      for (std::size_t x = 0; x < w; ++x) {
        if (!valid[x]) continue;
        ++inside;
        const auto back = lens->project(Eigen::Vector3d(dx[x], dy[x], dz[x]));
        if (!back) {
          ++refused;
          continue;
        }
        worst = std::max(worst, (*back - Eigen::Vector2d(static_cast<double>(x), y)).norm());
      }
    }
    WARN(what << ": worst ray_row round trip " << worst << " px over " << inside << " pixels");
    CHECK(refused == 0);
    CHECK(inside > 100000);
    CHECK(worst < 1e-6);
  }
}

TEST_CASE("Tabulated ray_row on the axis, at the edge of the field and from odd start columns", "[lens]") {
  Intrinsics k = imx250();
  k.cx = 1000, k.cy = 900;  // integral: a pixel centre sits on the axis (r = 0, the table's first node)
  const KannalaBrandtLens kb(k, std::array{0.012, -0.004, 0.0008, -0.00005}, 92.5 * kRadPerDeg);
  double dx[7], dy[7], dz[7];
  unsigned char valid[7];
  kb.ray_row(900, 997, 7, dx, dy, dz, valid);
  CHECK((valid[3] == 1 && dx[3] == 0 && dy[3] == 0 && dz[3] == 1));  // the axis itself, exactly
  for (int i = 0; i < 7; ++i) {
    const auto r = kb.ray(Eigen::Vector2d(997 + i, 900));
    REQUIRE(r);
    CHECK(angle_between(*r, {dx[i], dy[i], dz[i]}) <= kTabulatedRad);
  }
  // Along the row through the axis, the pixels on both sides of the image circle's edge: validity
  // exactly ray()'s, and the last pixel inside within the bound.
  const double edge = k.cx + k.fx * kb.distorted(kb.max_field_angle());
  const int x0 = static_cast<int>(std::floor(edge)) - 2;
  kb.ray_row(900, x0, 5, dx, dy, dz, valid);
  int in = 0;
  for (int i = 0; i < 5; ++i) {
    const auto r = kb.ray(Eigen::Vector2d(x0 + i, 900));
    CHECK(static_cast<bool>(r) == (valid[i] == 1));
    if (r) {
      ++in;
      CHECK(angle_between(*r, {dx[i], dy[i], dz[i]}) <= kTabulatedRad);
    } else {
      CHECK((dx[i] == 0 && dy[i] == 0 && dz[i] == 1));
    }
  }
  CHECK(in == 3);
  // A row and a start column that are not finite: no rays.
  kb.ray_row(std::nan(""), 0, 3, dx, dy, dz, valid);
  CHECK((valid[0] == 0 && valid[1] == 0 && valid[2] == 0 && dz[0] == 1));
}

TEST_CASE("sincos_0_pi is within 2 ulp of libm over [0, π]", "[lens]") {
  const detail::SinCosTable& t = detail::sincos_table();
  double worst_s = 0, worst_c = 0;
  for (int i = 0; i <= 1000000; ++i) {
    const double theta = std::numbers::pi * i / 1000000;
    double s, c;
    detail::sincos_0_pi(t, theta, s, c);
    worst_s = std::max(worst_s, std::abs(s - std::sin(theta)));
    worst_c = std::max(worst_c, std::abs(c - std::cos(theta)));
  }
  // 2 ulp of a number in [0.5, 1) is 2.2e-16: the absolute error of a value ≤ 1 stays below it.
  CHECK(worst_s <= 2.3e-16);
  CHECK(worst_c <= 2.3e-16);
}

TEST_CASE("The ray paths' sin and cos (detail::sin_cos) are the library's within 2 ulp, in every quadrant", "[lens]") {
  // Against std::sin and std::cos (correctly rounded to < 1 ulp in glibc): the Cody-Waite
  // reduction, the quadrant selection and the polynomials are all exercised by x over [-10, 10].
  std::size_t bad = 0;
  for (int i = -200000; i <= 200000; ++i) {
    for (double x : {i * 5e-5, i * 5e-5 + 1e-9}) {
      double s, c;
      detail::sin_cos(x, s, c);
      const double ulp = std::numeric_limits<double>::epsilon();
      const double ts = std::sin(x), tc = std::cos(x);
      bad += std::abs(s - ts) <= 2 * ulp * std::max(std::abs(ts), 0x1p-30) ? 0 : 1;
      bad += std::abs(c - tc) <= 2 * ulp * std::max(std::abs(tc), 0x1p-30) ? 0 : 1;
    }
  }
  CHECK(bad == 0);
  for (double x : {0.0, std::numbers::pi / 2, std::numbers::pi, 92.5 * kRadPerDeg}) {
    double s, c;
    detail::sin_cos(x, s, c);
    CHECK(std::abs(s - std::sin(x)) <= 2e-16);
    CHECK(std::abs(c - std::cos(x)) <= 2e-16);
  }
}
