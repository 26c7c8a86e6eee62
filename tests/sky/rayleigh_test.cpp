// The Rayleigh sky against the closed forms of the papers (Sun et al. 2019 eqs. 3–4, SkyPole
// eq. 1), the physics it must respect (E ⟂ sun and view, symmetry about the sun) and the hard cases.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>

#include "sky/rayleigh.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using namespace skypol::testing;

namespace {
// The local-meridian basis: e0 along the meridian towards the zenith (North at the zenith itself).
Eigen::Vector3d meridian_e0(const Eigen::Vector3d& d) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ() - d.z() * d;
  if (up.norm() < 1e-12) return d.z() > 0 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d(0, -1, 0);
  return up.normalized();
}

Stokes eval(const SkyModel& m, const Eigen::Vector3d& d, const Sun& s) { return m.stokes(d, meridian_e0(d), s); }
}  // namespace

TEST_CASE("DoLP is Pmax sin^2(g)/(1+cos^2(g)) with g from Sun et al.'s spherical formula", "[rayleigh][paper]") {
  // Sun et al. 2019 eq. 4 with γ = arccos(cosθ cosθs + sinθ sinθs cos(φ−φs)); SkyPole eq. 1 is
  // the case Pmax = 1, written (1 − cos²γ)/(1 + cos²γ).
  for (double pmax : {1.0, 0.7, 0.0}) {
    const RayleighSky sky({pmax});
    for (double ths = 0; ths <= 180; ths += 15) {  // sun zenith angle, including below the horizon
      for (double phs : {0.0, 37.0, 200.0}) {
        Sun sun;
        sun.direction = {std::sin(ths * kRadPerDeg) * std::cos(phs * kRadPerDeg), std::sin(ths * kRadPerDeg) * std::sin(phs * kRadPerDeg),
                         std::cos(ths * kRadPerDeg)};
        for (double th = 0; th <= 90; th += 10) {
          for (double ph = 0; ph < 360; ph += 30) {
            const Eigen::Vector3d d(std::sin(th * kRadPerDeg) * std::cos(ph * kRadPerDeg), std::sin(th * kRadPerDeg) * std::sin(ph * kRadPerDeg),
                                    std::cos(th * kRadPerDeg));
            const double cg = std::cos(th * kRadPerDeg) * std::cos(ths * kRadPerDeg) +
                              std::sin(th * kRadPerDeg) * std::sin(ths * kRadPerDeg) * std::cos((ph - phs) * kRadPerDeg);
            const double g = std::acos(std::clamp(cg, -1.0, 1.0));
            const double expected = pmax * std::sin(g) * std::sin(g) / (1 + std::cos(g) * std::cos(g));
            const Stokes s = eval(sky, d, sun);
            CHECK(s.dolp() == Approx(expected).margin(1e-12));
            if (pmax == 1.0) CHECK(s.dolp() == Approx((1 - cg * cg) / (1 + cg * cg)).margin(1e-12));
            CHECK(s.s0 == Approx(1 + cg * cg).margin(1e-12));
            CHECK(s.s3 == 0.0);
          }
        }
      }
    }
  }
}

TEST_CASE("AoLP matches Sun et al. eq. 3 wherever tan(alpha) is defined", "[rayleigh][paper]") {
  // Eq. 3: tan α = (sinθ cosθs − cosθ cos(φ−φs) sinθs) / (sin(φ−φs) sinθs), with the paper's
  // axes (X East, Y North, Z up; φ counted from X towards Y) and α the angle of the E-vector from
  // the local meridian. The paper counts α the other way round from skypol's basis
  // (e0 = meridian, e90 = d × e0 turns clockwise as the observer looking up sees it), so
  // α_paper = −AoLP (mod π). Undefined where the denominator vanishes (the solar meridian,
  // a sun at the zenith): skipped there, covered by the vector-form tests below.
  const RayleighSky sky;
  int compared = 0;
  for (double ths = 5; ths <= 175; ths += 17) {
    for (double phs : {10.0, 95.0, 260.0}) {
      Sun sun;
      sun.direction = {std::sin(ths * kRadPerDeg) * std::cos(phs * kRadPerDeg), std::sin(ths * kRadPerDeg) * std::sin(phs * kRadPerDeg),
                       std::cos(ths * kRadPerDeg)};
      for (double th = 3; th <= 90; th += 9) {
        for (double ph = 0; ph < 360; ph += 13) {
          const double den = std::sin((ph - phs) * kRadPerDeg) * std::sin(ths * kRadPerDeg);
          if (std::abs(den) < 1e-3) continue;
          const double num = std::sin(th * kRadPerDeg) * std::cos(ths * kRadPerDeg) -
                             std::cos(th * kRadPerDeg) * std::cos((ph - phs) * kRadPerDeg) * std::sin(ths * kRadPerDeg);
          const double alpha = std::atan(num / den);
          const Eigen::Vector3d d(std::sin(th * kRadPerDeg) * std::cos(ph * kRadPerDeg), std::sin(th * kRadPerDeg) * std::sin(ph * kRadPerDeg),
                                  std::cos(th * kRadPerDeg));
          const Stokes s = eval(sky, d, sun);
          if (s.dolp() < 1e-9) continue;  // at the sun/anti-sun AoLP is undefined
          CHECK(axial_diff(-s.aolp(), alpha) == Approx(0.0).margin(1e-9));
          ++compared;
        }
      }
    }
  }
  CHECK(compared > 3000);
}

TEST_CASE("the E-vector is perpendicular to the sun and to the view", "[rayleigh]") {
  std::mt19937_64 rng(7);
  const RayleighSky sky({0.8});
  for (int i = 0; i < 2000; ++i) {
    Sun sun;
    sun.direction = random_unit(rng);
    const Eigen::Vector3d d = random_unit(rng);
    // Any basis, not only the meridian one.
    const Eigen::Vector3d e0 = random_perpendicular(d, rng);
    const Stokes s = sky.stokes(d, e0, sun);
    if (s.dolp() < 1e-6) continue;
    const Eigen::Vector3d e = std::cos(s.aolp()) * e0 + std::sin(s.aolp()) * d.cross(e0);
    CHECK(std::abs(e.dot(sun.direction)) < 1e-9);
    CHECK(std::abs(e.dot(d)) < 1e-12);
  }
}

TEST_CASE("orientation: sun in the east gives a north-south E-vector at the zenith", "[rayleigh]") {
  const RayleighSky sky;
  const Eigen::Vector3d zenith(0, 0, 1), east(1, 0, 0);  // basis e0 = East, e90 = zenith × East = North
  CHECK(std::abs(axial_diff(sky.stokes(zenith, east, sun_at(90, 0)).aolp(), kPi / 2)) < 1e-12);
  CHECK(std::abs(axial_diff(sky.stokes(zenith, east, sun_at(0, 0)).aolp(), 0.0)) < 1e-12);
  CHECK(std::abs(axial_diff(sky.stokes(zenith, east, sun_at(45, 30)).aolp(), -kPi / 4)) < 1e-12);
  CHECK(sky.stokes(zenith, east, sun_at(90, 0)).dolp() == Approx(1.0));  // 90° from the sun
}

TEST_CASE("DoLP is symmetric about the sun and about the plane normal to it", "[rayleigh]") {
  std::mt19937_64 rng(11);
  const RayleighSky sky({0.75});
  for (int i = 0; i < 500; ++i) {
    Sun sun;
    sun.direction = random_unit(rng);
    const Eigen::Vector3d d = random_unit(rng);
    const double p = eval(sky, d, sun).dolp();
    const Eigen::AngleAxisd turn(std::uniform_real_distribution<double>(0, 2 * kPi)(rng), sun.direction);
    const Eigen::Vector3d rotated = turn * d;
    CHECK(eval(sky, rotated, sun).dolp() == Approx(p).margin(1e-12));
    const Eigen::Vector3d mirrored = d - 2 * d.dot(sun.direction) * sun.direction;  // SkyPole's plane symmetry
    CHECK(eval(sky, mirrored, sun).dolp() == Approx(p).margin(1e-12));
  }
}

TEST_CASE("hard cases are finite and agree with their limits", "[rayleigh][hard]") {
  const RayleighSky sky({0.7});
  const Eigen::Vector3d z(0, 0, 1), x(1, 0, 0);
  SECTION("sun at the zenith, looking at the sun and at the anti-sun") {
    Sun sun = sun_at(123, 90);
    // enu_direction(az, 90°) carries cos(π/2) ≈ 6e-17 in x and y: tiny but not zero.
    CHECK(std::abs(sky.stokes(z, x, sun).s1) < 1e-30);
    sun.direction = z;  // exactly at the zenith
    const Stokes at_sun = sky.stokes(z, x, sun);
    CHECK(at_sun.s0 == Approx(2.0));
    CHECK(at_sun.s1 == 0.0);  // exactly: E = d × s = 0
    CHECK(at_sun.s2 == 0.0);
    CHECK(at_sun.dolp() == 0.0);
    const Stokes anti = sky.stokes(-z, x, sun);
    CHECK(anti.s1 == 0.0);
    CHECK(anti.s2 == 0.0);
    CHECK(anti.s0 == Approx(2.0));
    // Horizon: γ = 90°, DoLP = Pmax in every azimuth; the E-vector is horizontal.
    for (double az = 0; az < 360; az += 45) {
      const Eigen::Vector3d d = enu_direction(az * kRadPerDeg, 0);
      const Stokes s = eval(sky, d, sun);
      CHECK(s.dolp() == Approx(0.7).margin(1e-12));
      CHECK(std::abs(axial_diff(s.aolp(), kPi / 2)) < 1e-12);  // ⟂ the meridian
    }
  }
  SECTION("near the sun the pattern goes continuously to zero") {
    const Sun sun = sun_at(200, 35);
    for (double eps : {1e-2, 1e-4, 1e-6}) {
      const Eigen::Vector3d d = enu_direction(200 * kRadPerDeg, (35 + eps) * kRadPerDeg);
      const double g = eps * kRadPerDeg;
      CHECK(eval(sky, d, sun).dolp() == Approx(0.7 * g * g / 2).epsilon(1e-3));  // sin²γ/(1+cos²γ) ≈ γ²/2
    }
  }
  SECTION("sun on and below the horizon") {
    for (double el : {0.0, -0.5, -10.0, -90.0}) {
      const Sun sun = sun_at(270, el);
      for (double az = 0; az < 360; az += 30) {
        for (double vel = 0; vel <= 90; vel += 15) {
          const Stokes s = eval(sky, enu_direction(az * kRadPerDeg, vel * kRadPerDeg), sun);
          CHECK(std::isfinite(s.s0));
          CHECK(std::isfinite(s.s1));
          CHECK(std::isfinite(s.s2));
          CHECK(s.dolp() <= 0.7 + 1e-12);
        }
      }
      if (el == 0.0) CHECK(eval(sky, z, sun).dolp() == Approx(0.7));  // zenith 90° from the sun
    }
  }
}

TEST_CASE("DoLP at the celestial pole depends only on the declination (SkyPole)", "[rayleigh][skypole]") {
  const RayleighSky sky;
  for (double lat : {43.287, -33.87, 0.0, 89.0}) {
    const Eigen::Vector3d ncp = north_celestial_pole(lat);
    for (double dec : {-23.0, 0.0, 12.0}) {
      const double sd = std::sin(dec * kRadPerDeg);
      for (double ha = -180; ha < 180; ha += 20) {
        const double phi = lat * kRadPerDeg, dr = dec * kRadPerDeg, w = ha * kRadPerDeg;
        Sun sun;
        sun.direction = {-std::cos(dr) * std::sin(w), std::sin(dr) * std::cos(phi) - std::cos(dr) * std::sin(phi) * std::cos(w),
                         std::cos(dr) * std::cos(phi) * std::cos(w) + std::sin(dr) * std::sin(phi)};
        CHECK(eval(sky, ncp, sun).dolp() == Approx((1 - sd * sd) / (1 + sd * sd)).margin(1e-12));
      }
    }
  }
}

TEST_CASE("the batch path equals the scalar path to float precision", "[rayleigh][batch]") {
  std::mt19937_64 rng(3);
  const RayleighSky sky({0.72});
  const Sun sun = sun_at(140, 25);
  std::vector<ViewRay> rays(1003);  // not a multiple of any vector width
  for (ViewRay& r : rays) {
    const Eigen::Vector3d d = random_unit(rng);
    const Eigen::Vector3d e0 = random_perpendicular(d, rng);
    r.d = d.cast<float>();
    r.e0 = e0.cast<float>();
  }
  for (const auto& [batch, scalar] : batch_and_scalar(sky, rays, sun)) {
    CHECK(batch.s0 == Approx(scalar.s0).margin(2e-6));
    CHECK(batch.s1 == Approx(scalar.s1).margin(2e-6));
    CHECK(batch.s2 == Approx(scalar.s2).margin(2e-6));
    CHECK(batch.s3 == 0.0f);
  }
}

TEST_CASE("the structure-of-arrays path equals the ViewRay path bit for bit", "[rayleigh][batch]") {
  std::mt19937_64 rng(4);
  const RayleighSky sky({0.81});
  const Sun sun = sun_at(75, 60);
  const std::size_t n = 517;  // not a multiple of any vector width
  std::vector<ViewRay> rays(n);
  std::vector<float> plane[6];
  for (auto& p : plane) p.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = random_unit(rng);
    rays[i].d = d.cast<float>();
    rays[i].e0 = meridian_e0(d).cast<float>();
    for (int k = 0; k < 3; ++k) {
      plane[k][i] = rays[i].d[k];
      plane[3 + k][i] = rays[i].e0[k];
    }
  }
  std::vector<StokesF> aos(n);
  sky.stokes(rays, sun, aos);
  std::vector<float> s0(n), s1(n), s2(n), s3(n, 7.0f);
  const SkyModel& model = sky;
  model.stokes_soa({n, plane[0].data(), plane[1].data(), plane[2].data(), plane[3].data(), plane[4].data(),
                    plane[5].data()},
                   sun, {s0.data(), s1.data(), s2.data(), s3.data()});
  for (std::size_t i = 0; i < n; ++i) {
    CHECK(s0[i] == aos[i].s0);
    CHECK(s1[i] == aos[i].s1);
    CHECK(s2[i] == aos[i].s2);
    CHECK(s3[i] == 0.0f);
  }
}

TEST_CASE("Pmax outside [0, 1] is refused", "[rayleigh][bad-input]") {
  CHECK_THROWS_WITH(RayleighSky({1.5}), Catch::Contains("max_dolp") && Catch::Contains("[0, 1]"));
  CHECK_THROWS_AS(RayleighSky({-0.1}), std::invalid_argument);
  CHECK_THROWS_AS(RayleighSky({std::nan("")}), std::invalid_argument);
}

TEST_CASE("batch throughput (informational)", "[.][benchmark]") {
  const RayleighSky sky({0.7});
  const Sun sun = sun_at(140, 25);
  std::vector<ViewRay> rays(1 << 16);
  std::mt19937_64 rng(5);
  for (ViewRay& r : rays) {
    const Eigen::Vector3d d = random_unit(rng);
    r.d = d.cast<float>();
    r.e0 = meridian_e0(d).cast<float>();
  }
  std::vector<StokesF> out(rays.size());
  const int reps = 400;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < reps; ++k) sky.stokes(rays, sun, out);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("rayleigh batch: %.0f Mrays/s on one core\n", static_cast<double>(rays.size()) * reps / s / 1e6);
  CHECK(out[7].s0 > 0);
}
