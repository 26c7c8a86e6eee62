// Every lens model: exact round trips over the whole image circle of a 185° lens, closed-form
// pixels from independent formulas, turnover handling, binning.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "camera/double_sphere.h"
#include "camera/intrinsics.h"
#include "camera/kannala_brandt.h"
#include "camera/magnification.h"
#include "camera/ocam_lens.h"
#include "camera/radial_lens.h"
#include "camera/tabulated_lens.h"
#include "camera_test_util.h"
#include "sky/units.h"

using namespace skypol::camera;
using namespace skypol::testing;
using skypol::kPi, skypol::kRadPerDeg;

namespace {
const std::string kOcamFile = std::string(SKYPOL_SOURCE_DIR) + "/tests/camera/data/ocam_calib_results.txt";

// Worst |project(ray(p)) − p| over pixels covering the whole image circle: the images of
// directions on a dense (θ, φ) grid up to and including θmax, and every 5th sensor pixel that
// ray() accepts. Also checks that no accepted pixel gives a non-unit or non-finite ray.
double worst_round_trip(const Lens& lens) {
  double worst = 0;
  auto check = [&](const Eigen::Vector2d& p) {
    const auto d = lens.ray(p);
    if (!d) return false;
    REQUIRE(d->allFinite());
    REQUIRE(std::abs(d->norm() - 1) < 1e-12);
    const auto q = lens.project(*d);
    REQUIRE(q);
    worst = std::max(worst, (*q - p).norm());
    return true;
  };
  const double tmax = lens.max_field_angle();
  for (int i = 0; i <= 600; ++i)
    for (int j = 0; j < 48; ++j) {
      const auto p = lens.project(dir(tmax * i / 600, 2 * kPi * j / 48 + 0.05));
      REQUIRE(p);
      REQUIRE(check(*p));
    }
  const auto& k = lens.intrinsics();
  for (int v = 0; v < k.height; v += 5)
    for (int u = 0; u < k.width; u += 5) check(Eigen::Vector2d(u, v));
  return worst;
}

// Pixels just beyond the edge of the image circle are masked.
void check_masked_outside(const Lens& lens) {
  const Eigen::Vector2d c = *lens.project({0, 0, 1});
  for (int j = 0; j < 16; ++j) {
    const Eigen::Vector2d e = *lens.project(dir(lens.max_field_angle(), 2 * kPi * j / 16 + 0.2));
    CHECK_FALSE(lens.ray(c + (e - c) * 1.001));
  }
  CHECK_FALSE(lens.project(dir(lens.max_field_angle() + 1e-6, 0.4)));
  // Garbage in: nullopt, never NaN.
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(std::nan(""), 100), Eigen::Vector2d(100, inf),
                                   Eigen::Vector2d(-1e300, 1e300)})
    CHECK_FALSE(lens.ray(p));
  CHECK_FALSE(lens.project({0, 0, 0}));
  CHECK_FALSE(lens.project({0, 0, -1}));
  CHECK_FALSE(lens.project({std::nan(""), 0, 1}));
}
}  // namespace

TEST_CASE("Kannala-Brandt with k = 0 is the equidistant lens; k1 = 0.1 at 1 rad gives θd = 1.1", "[lens]") {
  KannalaBrandtLens kb0(imx250(), {0, 0, 0, 0}, 92.5 * kRadPerDeg);
  const auto p = kb0.project({1, 0, 0});
  REQUIRE(p);
  CHECK(p->x() == Approx(1223.5 + kF * kPi / 2).epsilon(1e-14));
  KannalaBrandtLens kb1(imx250(), {0.1, 0, 0, 0}, 92.5 * kRadPerDeg);
  const auto q = kb1.project(dir(1.0, kPi / 2));  // straight down the image
  REQUIRE(q);
  CHECK(q->x() == Approx(1223.5).margin(1e-9));
  CHECK(q->y() == Approx(1023.5 + kF * 1.1).epsilon(1e-14));
  // k2..k4 enter as θ⁵, θ⁷, θ⁹: at θ = 0.5, 0.5·(1 + 0.01·0.0625 + 0.02·0.015625 − 0.001·0.00390625)
  KannalaBrandtLens kb2(imx250(), {0, 0.01, 0.02, -0.001}, 92.5 * kRadPerDeg);
  CHECK(kb2.distorted(0.5) == Approx(0.5 * (1 + 0.000625 + 0.0003125 - 0.00000390625)).epsilon(1e-15));
}

TEST_CASE("Kannala-Brandt past 90°: θ from atan2, not atan", "[lens]") {
  KannalaBrandtLens kb(imx250(), {-0.01, 0.002, 0, 0}, 92.5 * kRadPerDeg);
  const double t = 92 * kRadPerDeg;
  const auto p = kb.project(dir(t, 0));  // z < 0
  REQUIRE(p);
  const double t2 = t * t;
  CHECK(p->x() == Approx(1223.5 + kF * t * (1 - 0.01 * t2 + 0.002 * t2 * t2)).epsilon(1e-14));
}

TEST_CASE("Kannala-Brandt that turns over near the edge: rejected, or the FOV is cut there", "[lens]") {
  // θd = θ − aθ³ turns over where 1 − 3aθ² = 0; a = 1/(3·θt²) puts it at θt = 93°.
  const double tt = 93 * kRadPerDeg, a = 1 / (3 * tt * tt);
  CHECK_NOTHROW(KannalaBrandtLens(imx250(), {-a, 0, 0, 0}, 92.5 * kRadPerDeg));
  CHECK_THROWS_WITH(KannalaBrandtLens(imx250(), {-a, 0, 0, 0}, 95 * kRadPerDeg),
                    "distortion curve not monotone over the declared field of view (turns over at 93.0°)");
  KannalaBrandtLens cut(imx250(), {-a, 0, 0, 0}, 95 * kRadPerDeg, KannalaBrandtLens::OnTurnover::clamp_fov);
  CHECK(cut.max_field_angle() == Approx(tt).epsilon(1e-12));
  CHECK_FALSE(cut.project(dir(94 * kRadPerDeg, 0)));  // beyond the turning point: not imaged
}

TEST_CASE("double sphere with ξ = 0, α = ½ is the stereographic lens 2 tan(θ/2)", "[lens]") {
  DoubleSphereLens ds(imx250(), 0.0, 0.5, 100 * kRadPerDeg);
  for (double t : {0.1, 0.8, 1.5, 1.7}) CHECK(ds.radius(t) == Approx(2 * std::tan(t / 2)).epsilon(1e-14));
  CHECK(DoubleSphereLens::valid_angle(0, 0.5) == Approx(kPi));
  // ξ = −0.2, α = 0.6: w1 = 2/3, w2 = (2/3 − 0.2)/√(1 − 0.8/3 + 0.04) = 0.5307 → limit acos(−w2) = 122.05°.
  const double w2 = (2.0 / 3 - 0.2) / std::sqrt(2 * (2.0 / 3) * -0.2 + 0.04 + 1);
  CHECK(DoubleSphereLens::valid_angle(-0.2, 0.6) == Approx(std::acos(-w2)).epsilon(1e-14));
  CHECK(std::acos(-w2) / kRadPerDeg == Approx(122.05).margin(0.01));
  CHECK_THROWS_WITH(DoubleSphereLens(imx250(), -0.2, 0.6, 125 * kRadPerDeg), Catch::Contains("limit of 122.1°"));
  CHECK_THROWS_WITH(DoubleSphereLens(imx250(), 0.1, 1.5, 1.0), Catch::Contains("alpha"));
}

TEST_CASE("tabulated heights: linear table reproduced exactly, smooth table to 3e-5 mm", "[lens]") {
  // Equidistant 1.8 mm lens, every 10°: h = f·θ. Fritsch–Carlson keeps a straight line straight.
  std::vector<std::pair<double, double>> lin, sol;
  for (int d = 10; d <= 90; d += 10) lin.emplace_back(d, 1.8 * d * kRadPerDeg);
  lin.emplace_back(92.5, 1.8 * 92.5 * kRadPerDeg);
  Intrinsics k = imx250(1 / 3.45e-3);  // pixels per mm
  TabulatedLens tl(k, height_table_from_deg_mm(lin));
  const auto p = tl.project(dir(45 * kRadPerDeg, 0));
  REQUIRE(p);
  CHECK(p->x() == Approx(1223.5 + 1.8 / 3.45e-3 * kPi / 4).epsilon(1e-12));
  // Equisolid 2f·sin(θ/2) every 5°: the cubic is within 3e-5 mm (0.01 px) in between
  // (worst in the first segment, 0–5°, where only the added (0, 0) point bounds it).
  for (int d = 5; d <= 90; d += 5) sol.emplace_back(d, 2 * 1.8 * std::sin(d * kRadPerDeg / 2));
  TabulatedLens ts(k, height_table_from_deg_mm(sol));
  double worst = 0;
  for (double t = 0; t <= 90 * kRadPerDeg; t += 0.01 * kRadPerDeg)
    worst = std::max(worst, std::abs(ts.height(t) - 2 * 1.8 * std::sin(t / 2)));
  CHECK(worst < 3e-5);
  CHECK(ts.angle(ts.height(0.7)) == Approx(0.7).epsilon(1e-14));
  // A table that turns over is an error naming the angle.
  auto bad = sol;
  bad[15].second = bad[14].second;  // 80° no higher than 75°
  CHECK_THROWS_WITH(TabulatedLens(k, height_table_from_deg_mm(bad)), "image height table not monotone at 80.0°");
}

TEST_CASE("OCamCalib calib_results.txt loads in its documented order", "[lens]") {
  const OCamModel m = load_ocamcalib(kOcamFile);
  REQUIRE(m.pol.size() == 5);
  CHECK(m.pol[0] == -260.87);
  CHECK(m.pol[4] == 1.2556e-9);
  REQUIRE(m.invpol.size() == 10);
  CHECK(m.invpol[0] == 417.495108);
  CHECK(m.xc == 511.3);  // row
  CHECK(m.yc == 612.8);  // column
  CHECK(m.c == 1.0002);
  CHECK(m.d == 0.0003);
  CHECK(m.e == -0.0002);
  CHECK(m.height == 1024);
  CHECK(m.width == 1224);
  CHECK_THROWS_WITH(load_ocamcalib("/nonexistent/calib.txt"), Catch::Contains("cannot open"));
}

TEST_CASE("OCam lens: axis at (yc, xc), 90° where pol(ρ) = 0, invpol agrees with the exact inverse", "[lens]") {
  OCamLens lens(load_ocamcalib(kOcamFile), 92.5 * kRadPerDeg);
  const auto c = lens.project({0, 0, 1});
  REQUIRE(c);
  CHECK(c->x() == Approx(612.8));
  CHECK(c->y() == Approx(511.3));
  // θ = 90°: pol(ρ) = a0 + a2ρ² + a4ρ⁴ = 0, a quadratic in ρ².
  const double a0 = -260.87, a2 = 1.2778e-3, a4 = 1.2556e-9;
  const double rho90 = std::sqrt((-a2 + std::sqrt(a2 * a2 - 4 * a4 * a0)) / (2 * a4));
  // Camera +x is OCam's Y (columns): pre-affine (x', y') = (0, ρ) → row = d·ρ + xc, col = ρ + yc.
  const auto p = lens.project({1, 0, 0});
  REQUIRE(p);
  CHECK(p->x() == Approx(rho90 + 612.8).epsilon(1e-13));
  CHECK(p->y() == Approx(0.0003 * rho90 + 511.3).epsilon(1e-13));
  // OCamCalib's own invpol (the file's world2cam) at t = θ − 90° = 0 gives nearly the same ρ.
  CHECK(load_ocamcalib(kOcamFile).invpol[0] == Approx(rho90).margin(0.01));
  // Camera +y is OCam's X (rows): pre-affine (ρ, 0) → row = c·ρ + xc, col = e·ρ + yc.
  const auto q = lens.project({0, 1, 0});
  REQUIRE(q);
  CHECK(q->x() == Approx(-0.0002 * rho90 + 612.8).epsilon(1e-13));
  CHECK(q->y() == Approx(1.0002 * rho90 + 511.3).epsilon(1e-13));
}

TEST_CASE("project(ray(p)) = p to 1e-6 px over the whole image circle of a 185° lens, every model", "[lens]") {
  const double tt = 93 * kRadPerDeg, a = 1 / (3 * tt * tt);
  struct Named {
    std::string what;
    std::shared_ptr<const Lens> lens;
  };
  std::vector<std::pair<double, double>> sol;
  for (int d = 5; d <= 90; d += 5) sol.emplace_back(d, 2 * 1.8 * std::sin(d * kRadPerDeg / 2));
  sol.emplace_back(92.5, 2 * 1.8 * std::sin(92.5 * kRadPerDeg / 2));
  const std::vector<Named> lenses = {
      {"equidistant", std::make_shared<RadialLens>(Mapping::equidistant, imx250(), 92.5 * kRadPerDeg)},
      {"equisolid", std::make_shared<RadialLens>(Mapping::equisolid, imx250(), 92.5 * kRadPerDeg)},
      {"stereographic", std::make_shared<RadialLens>(Mapping::stereographic, imx250(), 92.5 * kRadPerDeg)},
      {"kannala_brandt", std::make_shared<KannalaBrandtLens>(imx250(), std::array{0.012, -0.004, 0.0008, -0.00005}, 92.5 * kRadPerDeg)},
      {"kannala_brandt turning over at 93° (cut there)",
       std::make_shared<KannalaBrandtLens>(imx250(), std::array{-a, 0.0, 0.0, 0.0}, 95 * kRadPerDeg,
                                           KannalaBrandtLens::OnTurnover::clamp_fov)},
      {"kannala_brandt turning over just past 92.5°",
       std::make_shared<KannalaBrandtLens>(imx250(), std::array{-1 / (3 * std::pow(92.51 * kRadPerDeg, 2)), 0.0, 0.0, 0.0}, 92.5 * kRadPerDeg)},
      {"double_sphere", std::make_shared<DoubleSphereLens>(imx250(), -0.2, 0.6, 92.5 * kRadPerDeg)},
      {"tabulated", std::make_shared<TabulatedLens>(imx250(1 / 3.45e-3), height_table_from_deg_mm(sol))},
      {"ocam", std::make_shared<OCamLens>(load_ocamcalib(kOcamFile), 92.5 * kRadPerDeg)},
  };
  for (const auto& [what, lens] : lenses) {
    INFO(what);
    const double worst = worst_round_trip(*lens);
    WARN(what << ": worst round-trip error " << worst << " px");
    CHECK(worst < 1e-6);
    check_masked_outside(*lens);
    // A binned copy sees every direction at (p + ½)/2 − ½.
    const auto b = binned(*lens, 2);
    for (double t : {0.0, 0.4, 1.2, 1.6})
      for (double phi : {0.3, 2.0, 4.0}) {
        const auto p = lens->project(dir(t, phi));
        const auto q = b->project(dir(t, phi));
        REQUIRE(p);
        REQUIRE(q);
        CHECK((*q - ((*p).array() + 0.5).matrix() / 2 + Eigen::Vector2d(0.5, 0.5)).norm() < 1e-9);
      }
    CHECK(b->intrinsics().width == lens->intrinsics().width / 2);
    CHECK(b->intrinsics().height == lens->intrinsics().height / 2);
  }
}

TEST_CASE("binning by 2: fx/2, cx' = (cx + 0.5)/2 − 0.5", "[lens]") {
  RadialLens lens(Mapping::equidistant, imx250(), 92.5 * kRadPerDeg);
  const auto b = binned(lens, 2);
  CHECK(b->intrinsics().fx == Approx(kF / 2));
  CHECK(b->intrinsics().cx == Approx(611.5));
  CHECK(b->intrinsics().cy == Approx(511.5));
  CHECK(b->intrinsics().width == 1224);
  CHECK(b->intrinsics().height == 1024);
  CHECK_THROWS_AS(binned(lens, 0), std::invalid_argument);
}

TEST_CASE("image circle of the 185° fisheye on the IMX250: r = f·92.5° = 842.3 px, fits", "[lens]") {
  RadialLens lens(Mapping::equidistant, imx250(), 92.5 * kRadPerDeg);
  const ImageCircle c = image_circle(lens);
  CHECK(c.radius_px == Approx(kF * 92.5 * kRadPerDeg).epsilon(1e-9));
  CHECK(c.radius_px == Approx(842.3).margin(0.05));
  CHECK(c.fits_on_sensor);
  CHECK(c.max_fov_deg == Approx(185));
  CHECK(c.full_circle_fov_deg == Approx(185));
  CHECK(c.centre.x() == 1223.5);
  // A longer focal length (700 px) clips top and bottom: the full circle reaches only
  // θ = (cy + 0.5)/f = 1024/700 rad, 2θ = 167.6°.
  RadialLens tele(Mapping::equidistant, imx250(700), 92.5 * kRadPerDeg);
  const ImageCircle t = image_circle(tele);
  CHECK_FALSE(t.fits_on_sensor);
  CHECK(t.full_circle_fov_deg == Approx(2 * 1024.0 / 700 / kRadPerDeg).epsilon(1e-6));
}

TEST_CASE("intrinsics from mm: 1.8 mm on 3.45 µm pixels is 521.739 px, centred", "[lens]") {
  const Intrinsics k = intrinsics_from_mm(1.8, 3.45, 2448, 2048);
  CHECK(k.fx == Approx(521.739).margin(1e-3));
  CHECK(k.fy == k.fx);
  CHECK(k.cx == 1223.5);
  CHECK(k.cy == 1023.5);
  CHECK_THROWS_WITH(intrinsics_from_mm(0, 3.45, 10, 10), "focal_mm must be > 0");
  CHECK_THROWS_WITH(intrinsics_from_mm(1.8, -1, 10, 10), "pitch_um must be > 0");
}

TEST_CASE("Kannala-Brandt: a derivative that only touches zero between scan samples is still caught", "[lens]") {
  // g(u) = dθd/dθ = 1 + 3k1·u + 5k2·u² = 5k2·(u − u0)² has a double root at u0 = (80°)²: the
  // curve flattens to zero slope at 80° without changing sign.
  const double u0 = std::pow(80 * kRadPerDeg, 2);
  const double k2 = 1 / (5 * u0 * u0), k1 = -2 * u0 * 5 * k2 / 3;
  KannalaBrandtLens probe(imx250(), {k1, k2, 0, 0}, 70 * kRadPerDeg);
  CHECK(probe.distorted_derivative(80 * kRadPerDeg) == Approx(0).margin(1e-12));
  CHECK_THROWS_WITH(KannalaBrandtLens(imx250(), {k1, k2, 0, 0}, 92.5 * kRadPerDeg),
                    Catch::Contains("turns over at 80.0°"));
}

TEST_CASE("magnifications match Sun et al. 2019 eqs. 23-28", "[lens]") {
  const double f = kF;
  for (double t : {0.0, 0.3, 1.0, kPi / 2, 1.6}) {
    const double th = std::max(t, 1e-12);
    auto eqd = magnification(RadialLens(Mapping::equidistant, imx250(), 92.5 * kRadPerDeg), t, 0.7);
    auto eqs = magnification(RadialLens(Mapping::equisolid, imx250(), 92.5 * kRadPerDeg), t, 0.7);
    auto stg = magnification(RadialLens(Mapping::stereographic, imx250(), 92.5 * kRadPerDeg), t, 0.7);
    REQUIRE(eqd);
    REQUIRE(eqs);
    REQUIRE(stg);
    INFO("theta " << t);
    CHECK(eqd->radial_px == Approx(f).epsilon(1e-6));                                 // eq. 23
    CHECK(eqd->tangential_px == Approx(t == 0 ? f : f * th / std::sin(th)).epsilon(1e-6));  // eq. 24
    CHECK(eqs->radial_px == Approx(f * std::cos(t / 2)).epsilon(1e-6));               // eq. 25
    CHECK(eqs->tangential_px == Approx(f / std::cos(t / 2)).epsilon(1e-6));           // eq. 26
    CHECK(stg->radial_px == Approx(f / std::pow(std::cos(t / 2), 2)).epsilon(1e-6));  // eq. 27
    CHECK(stg->tangential_px == Approx(f / std::pow(std::cos(t / 2), 2)).epsilon(1e-6));  // eq. 28
  }
  // At 90°: β_t = 1.571f (equidistant), 1.414f (equisolid), β = 2f (stereographic), as the paper says.
  CHECK(magnification(RadialLens(Mapping::equisolid, imx250(), 92.5 * kRadPerDeg), kPi / 2, 0)->tangential_px / f ==
        Approx(std::sqrt(2.0)));
  CHECK_FALSE(magnification(RadialLens(Mapping::equidistant, imx250(), 92.5 * kRadPerDeg), 93 * kRadPerDeg, 0));
}

TEST_CASE("parameters() lists each model's values in its documented order", "[lens]") {
  KannalaBrandtLens kb(imx250(), {0.1, 0.02, 0.003, 0.0004}, 92.5 * kRadPerDeg);
  const auto p = kb.parameters();
  REQUIRE(p.size() == 11);
  CHECK(p[0] == std::pair<std::string, double>{"fx", kF});
  CHECK(p[2].first == "cx");
  CHECK(p[6].first == "fov_deg");
  CHECK(p[6].second == Approx(185));
  CHECK(p[7] == std::pair<std::string, double>{"k1", 0.1});
  CHECK(p[10] == std::pair<std::string, double>{"k4", 0.0004});
  const auto d = DoubleSphereLens(imx250(), -0.2, 0.6, 92.5 * kRadPerDeg).parameters();
  CHECK(d[7] == std::pair<std::string, double>{"xi", -0.2});
  CHECK(d[8] == std::pair<std::string, double>{"alpha", 0.6});
  const auto o = OCamLens(load_ocamcalib(kOcamFile), 92.5 * kRadPerDeg).parameters();
  CHECK(o[0] == std::pair<std::string, double>{"a0", -260.87});
  CHECK(o[5] == std::pair<std::string, double>{"p0", 417.495108});
  CHECK(o[15] == std::pair<std::string, double>{"xc", 511.3});
}
