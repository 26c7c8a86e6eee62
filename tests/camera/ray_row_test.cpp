// Lens::ray_row and Camera::ray_row, the renderer's batched ray paths, give bit for bit what ray()
// gives pixel by pixel, for every model (the ones that override ray_row and the base version),
// including the principal point, the edge of the image circle and pixels outside it.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "camera/camera.h"
#include "camera/double_sphere.h"
#include "camera/kannala_brandt.h"
#include "camera/ocam_lens.h"
#include "camera/radial_lens.h"
#include "camera/tabulated_lens.h"
#include "camera_test_util.h"

using namespace skypol::camera;
using namespace skypol::testing;

namespace {
constexpr double kDeg = std::numbers::pi / 180;
const std::string kOcamFile = std::string(SKYPOL_SOURCE_DIR) + "/tests/camera/data/ocam_calib_results.txt";

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Named {
  std::string what;
  std::shared_ptr<const Lens> lens;
};

std::vector<Named> lenses() {
  std::vector<std::pair<double, double>> table;
  for (int d = 5; d <= 90; d += 5) table.emplace_back(d, 2 * 1.8 * std::sin(d * kDeg / 2));
  table.emplace_back(92.5, 2 * 1.8 * std::sin(92.5 * kDeg / 2));
  Intrinsics off = imx250();
  off.cx = 1100.25, off.cy = 990.75, off.fy = kF * 1.01;  // principal point off the centre, fx ≠ fy
  return {
      {"equidistant", std::make_shared<RadialLens>(Mapping::equidistant, imx250(), 92.5 * kDeg)},
      {"equidistant, off-centre, fx != fy", std::make_shared<RadialLens>(Mapping::equidistant, off, 92.5 * kDeg)},
      {"equisolid", std::make_shared<RadialLens>(Mapping::equisolid, imx250(), 92.5 * kDeg)},
      {"equisolid 180", std::make_shared<RadialLens>(Mapping::equisolid, imx250(400), 180 * kDeg)},
      {"stereographic", std::make_shared<RadialLens>(Mapping::stereographic, imx250(), 92.5 * kDeg)},
      {"orthographic", std::make_shared<RadialLens>(Mapping::orthographic, imx250(900), 90 * kDeg)},
      {"perspective", std::make_shared<RadialLens>(Mapping::perspective, imx250(700), 60 * kDeg)},
      {"tabulated", std::make_shared<TabulatedLens>(imx250(1 / 3.45e-3), height_table_from_deg_mm(table))},
      {"kannala_brandt (base ray_row)",
       std::make_shared<KannalaBrandtLens>(imx250(), std::array{0.012, -0.004, 0.0008, -0.00005}, 92.5 * kDeg)},
      {"double_sphere (base ray_row)", std::make_shared<DoubleSphereLens>(imx250(), -0.2, 0.6, 92.5 * kDeg)},
      {"ocam (base ray_row)", std::make_shared<OCamLens>(load_ocamcalib(kOcamFile), 92.5 * kDeg)},
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

TEST_CASE("Lens::ray_row is ray() bit for bit, every model, whole rows", "[lens]") {
  for (const auto& [what, lens] : lenses()) {
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
        if (!same_bits(r->x(), dx[x]) || !same_bits(r->y(), dy[x]) || !same_bits(r->z(), dz[x])) ++mismatches;
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
  const RadialLens lens(Mapping::equisolid, k, 92.5 * kDeg);
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

TEST_CASE("Camera::ray_row is Camera::ray cast to float, bit for bit, under a tilted orientation", "[camera]") {
  const Eigen::Matrix3d r =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  for (const auto& [what, lens] : lenses()) {
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
        for (int c = 0; c < 7; ++c) mismatches += same_bits(got[c], want[c]) ? 0 : 1;
      }
    }
    CHECK(mismatches == 0);
  }
}
