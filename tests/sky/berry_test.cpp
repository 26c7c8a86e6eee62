// The Berry–Dennis–Lee sky: Rayleigh at zero separation, neutral points where BDL put them, each
// of index ½ (the line field turns by half a turn around it), bounded DoLP, mirror symmetry.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "sky/berry.h"
#include "sky/rayleigh.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using namespace skypol::testing;

namespace {
// Total turn of the E-vector line field (in units of full turns) along a small circle of
// angular radius r around the point c, walked counter-clockwise about c as seen from outside the
// sphere. The angle is measured in a basis parallel-transported along with the walk (e0 = the
// fixed vector t projected onto each tangent plane), so a regular field gives 0.
double line_field_index(const SkyModel& m, const Sun& sun, const Eigen::Vector3d& c, double r) {
  const Eigen::Vector3d t = perpendicular(c), u = c.cross(t);
  const int n = 720;
  double total = 0, prev = 0;
  for (int k = 0; k <= n; ++k) {
    const double a = 2 * kPi * k / n;
    const Eigen::Vector3d d = (std::cos(r) * c + std::sin(r) * (std::cos(a) * t + std::sin(a) * u)).normalized();
    // e0: the circle's centre direction projected (points from d towards c); e90 = d × e0.
    const Eigen::Vector3d e0 = (c - c.dot(d) * d).normalized();
    // The AoLP in that basis, plus the turn of the basis itself relative to a fixed frame (a).
    const double angle = m.stokes(d, e0, sun).aolp() + a;
    if (k > 0) total += std::remainder(angle - prev, kPi);
    prev = angle;
  }
  return total / (2 * kPi);
}
}  // namespace

TEST_CASE("zero separation reproduces the Rayleigh sky to 1e-9", "[berry]") {
  std::mt19937_64 rng(21);
  for (double pmax : {1.0, 0.63}) {
    const BerrySky berry({pmax, 0.0});
    const RayleighSky rayleigh({pmax});
    for (int i = 0; i < 5000; ++i) {
      Sun sun;
      sun.direction = random_unit(rng);
      sun.azimuth = azimuth_of(sun.direction);
      const Eigen::Vector3d d = random_unit(rng);
      const Eigen::Vector3d e0 = random_perpendicular(d, rng);
      const Stokes b = berry.stokes(d, e0, sun), r = rayleigh.stokes(d, e0, sun);
      CHECK(std::abs(b.s0 - r.s0) < 1e-9);
      CHECK(std::abs(b.s1 - r.s1) < 1e-9);
      CHECK(std::abs(b.s2 - r.s2) < 1e-9);
      CHECK(b.s3 == 0.0);
    }
  }
}

TEST_CASE("neutral points: on the solar vertical, unpolarized, Babinet above the sun", "[berry]") {
  const BerrySky berry({0.8, 20.0});
  for (double el : {-5.0, 0.0, 10.0, 40.0, 75.0, 90.0}) {
    const Sun sun = sun_at(135, el);
    const auto [babinet, brewster] = berry.neutral_points(sun);
    INFO("sun elevation " << el);
    CHECK(std::acos(std::clamp(babinet.dot(sun.direction), -1.0, 1.0)) / kRadPerDeg == Approx(20.0).margin(1e-9));
    CHECK(std::acos(std::clamp(brewster.dot(sun.direction), -1.0, 1.0)) / kRadPerDeg == Approx(20.0).margin(1e-9));
    // In the vertical plane through the sun: ⟂ to its horizontal normal (cos az, −sin az, 0).
    const Eigen::Vector3d normal(std::cos(135 * kRadPerDeg), -std::sin(135 * kRadPerDeg), 0);
    CHECK(std::abs(babinet.dot(normal)) < 1e-12);
    CHECK(std::abs(brewster.dot(normal)) < 1e-12);
    // Babinet 20° higher than the sun (past the zenith it comes down the other side)
    if (el < 90) CHECK(elevation_of(babinet) / kRadPerDeg == Approx(90 - std::abs(70 - el)).margin(1e-9));
    CHECK(elevation_of(brewster) / kRadPerDeg == Approx(el - 20).margin(1e-9));
    for (const Eigen::Vector3d& p : {babinet, brewster, Eigen::Vector3d(-babinet), Eigen::Vector3d(-brewster)}) {
      const Stokes s = berry.stokes(p, perpendicular(p), sun);
      CHECK(std::abs(s.s1) < 1e-14);
      CHECK(std::abs(s.s2) < 1e-14);
      CHECK(s.s0 > 0);
    }
  }
}

TEST_CASE("each neutral point has index 1/2; the pair around the sun adds up to Rayleigh's 1", "[berry]") {
  const Sun sun = sun_at(200, 30);
  const BerrySky berry({1.0, 15.0});
  const RayleighSky rayleigh;
  const auto [babinet, brewster] = berry.neutral_points(sun);
  const double r_small = 5 * kRadPerDeg, r_large = 30 * kRadPerDeg;
  const double rayleigh_sun = line_field_index(rayleigh, sun, sun.direction, r_small);
  CHECK(std::abs(rayleigh_sun) == Approx(1.0).margin(1e-9));
  CHECK(line_field_index(berry, sun, babinet, r_small) == Approx(rayleigh_sun / 2).margin(1e-9));
  CHECK(line_field_index(berry, sun, brewster, r_small) == Approx(rayleigh_sun / 2).margin(1e-9));
  CHECK(line_field_index(berry, sun, -babinet, r_small) == Approx(rayleigh_sun / 2).margin(1e-9));  // 4th
  CHECK(line_field_index(berry, sun, -brewster, r_small) == Approx(rayleigh_sun / 2).margin(1e-9));  // Arago
  CHECK(line_field_index(berry, sun, sun.direction, r_small) == Approx(0.0).margin(1e-9));  // none inside
  CHECK(line_field_index(berry, sun, sun.direction, r_large) == Approx(rayleigh_sun).margin(1e-9));
}

TEST_CASE("DoLP stays within [0, Pmax], is mirror-symmetric about the solar vertical, batch = scalar", "[berry]") {
  std::mt19937_64 rng(5);
  const BerrySky berry({0.7, 25.0});
  const Sun sun = sun_at(60, 35);
  const Eigen::Vector3d normal(std::cos(60 * kRadPerDeg), -std::sin(60 * kRadPerDeg), 0);  // of the solar vertical plane
  std::vector<ViewRay> rays;
  double max_seen = 0;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::Vector3d d = random_unit(rng);
    const double p = berry.stokes(d, perpendicular(d), sun).dolp();
    CHECK(p >= 0.0);
    CHECK(p <= 0.7 + 1e-12);
    max_seen = std::max(max_seen, p);
    const Eigen::Vector3d mirrored = d - 2 * d.dot(normal) * normal;
    CHECK(berry.stokes(mirrored, perpendicular(mirrored), sun).dolp() == Approx(p).margin(1e-12));
    rays.push_back({d.cast<float>(), perpendicular(d).cast<float>()});
  }
  CHECK(max_seen > 0.69);  // the maximum is still reached (on the great circle 90° from the sun)
  for (const auto& [batch, scalar] : batch_and_scalar(berry, rays, sun)) {
    CHECK(batch.s0 == Approx(scalar.s0).margin(2e-6));
    CHECK(batch.s1 == Approx(scalar.s1).margin(2e-6));
    CHECK(batch.s2 == Approx(scalar.s2).margin(2e-6));
  }
}

TEST_CASE("berry hard cases: sun at the zenith and below the horizon are finite", "[berry][hard]") {
  const BerrySky berry({0.8, 30.0});
  for (double el : {90.0, -90.0, -3.0, 0.0}) {
    const Sun sun = sun_at(10, el);
    for (double az = 0; az < 360; az += 20) {
      for (double vel = -90; vel <= 90; vel += 10) {
        const Eigen::Vector3d d = enu_direction(az * kRadPerDeg, vel * kRadPerDeg);
        const Stokes s = berry.stokes(d, perpendicular(d), sun);
        CHECK(std::isfinite(s.s1));
        CHECK(std::isfinite(s.s2));
        CHECK(s.dolp() <= 0.8 + 1e-12);
      }
    }
  }
}

namespace {
// BDL's eq. 4.2 evaluated as printed, in the stereographic plane (independent of berry.cpp's
// vector form): ζ = tan(θ/2) e^{iφ} (θ zenith angle, φ azimuth), the sun's pair at ζ± on the
// solar vertical, their antipodes −1/ζ±*, and
//   w = −4 (ζ − ζ+)(ζ − ζ−)(ζ + 1/ζ+*)(ζ + 1/ζ−*) / ((1 + |ζ|²)² |ζ+ + 1/ζ+*| |ζ− + 1/ζ−*|),
// normalised to max |w| = 1. Returns |w|.
double bdl_w_modulus(const Eigen::Vector3d& d, double sun_zenith, double sun_azimuth, double delta) {
  using C = std::complex<double>;
  const auto zeta = [](double zenith, double azimuth) { return std::tan(zenith / 2) * std::polar(1.0, azimuth); };
  const C z = zeta(std::acos(std::clamp(d.z(), -1.0, 1.0)), std::atan2(d.x(), d.y()));
  const C zp = zeta(sun_zenith - delta, sun_azimuth), zm = zeta(sun_zenith + delta, sun_azimuth);
  const C ap = -1.0 / std::conj(zp), am = -1.0 / std::conj(zm);
  const C w = -4.0 * (z - zp) * (z - zm) * (z - ap) * (z - am) /
              (std::pow(1.0 + std::norm(z), 2) * std::abs(zp - ap) * std::abs(zm - am));
  return std::abs(w);
}
}  // namespace

TEST_CASE("BDL eq. 4.2's |w| is sin g1 sin g2; each normalisation turns it into its degree", "[berry]") {
  // Sun 30° from the zenith at azimuth 40°, each neutral point 15° from it (a pair 30° apart).
  const double sun_zenith = 30 * kRadPerDeg, sun_az = 40 * kRadPerDeg, delta = 15 * kRadPerDeg;
  const Sun sun = sun_at(40, 60);
  const BerrySky split({1.0, 15.0});
  const BerrySky opensky({1.0, 15.0, BerryNormalisation::opensky});
  const auto [p1, p2] = split.neutral_points(sun);
  std::mt19937_64 rng(9);
  double largest_difference = 0;
  for (int i = 0; i < 3000; ++i) {
    Eigen::Vector3d d = random_unit(rng);
    if (d.z() < 0.05) d.z() = -d.z() + 0.05;  // the upper sky, where ζ is finite and well scaled
    d.normalize();
    const double w = bdl_w_modulus(d, sun_zenith, sun_az, delta);
    const double g1 = std::acos(std::clamp(d.dot(p1), -1.0, 1.0)), g2 = std::acos(std::clamp(d.dot(p2), -1.0, 1.0));
    INFO("d = " << d.transpose());
    CHECK(w == Approx(std::sin(g1) * std::sin(g2)).margin(1e-9));
    const Eigen::Vector3d e0 = perpendicular(d);
    const double a = split.stokes(d, e0, sun).dolp(), b = opensky.stokes(d, e0, sun).dolp();
    CHECK(a == Approx(w / (1 + std::cos(g1) * std::cos(g2))).margin(1e-9));
    CHECK(b == Approx(w / (2 - w)).margin(1e-9));
    CHECK(split.stokes(d, e0, sun).aolp() == Approx(opensky.stokes(d, e0, sun).aolp()).margin(1e-9));
    largest_difference = std::max(largest_difference, std::abs(a - b));
  }
  CHECK(largest_difference > 0.05);  // they do differ (up to 0.126 over the whole sphere)

  // One value by hand: sun at the zenith, δ = 15°, a direction 45° from the zenith in the plane
  // of the pair: γ1 = 30°, γ2 = 60°, |w| = sin 30° sin 60° = 0.4330127.
  const Sun overhead = sun_at(0, 90);
  const Eigen::Vector3d d = enu_direction(0, 45 * kRadPerDeg);
  CHECK(bdl_w_modulus(d, 0, 0, delta) == Approx(0.4330127).margin(1e-7));
  CHECK(split.stokes(d, perpendicular(d), overhead).dolp() == Approx(0.4330127 / (1 + std::cos(30 * kRadPerDeg) * 0.5)).margin(1e-7));
  CHECK(opensky.stokes(d, perpendicular(d), overhead).dolp() == Approx(0.4330127 / (2 - 0.4330127)).margin(1e-7));
}

TEST_CASE("opensky normalisation: Rayleigh at zero separation, batch = scalar, bounded", "[berry]") {
  std::mt19937_64 rng(33);
  const BerrySky zero({0.8, 0.0, BerryNormalisation::opensky});
  const RayleighSky rayleigh({0.8});
  const BerrySky berry({0.8, 25.0, BerryNormalisation::opensky});
  const Sun sun = sun_at(120, 20);
  std::vector<ViewRay> rays;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d d = random_unit(rng);
    const Eigen::Vector3d e0 = random_perpendicular(d, rng);
    const Stokes b = zero.stokes(d, e0, sun), r = rayleigh.stokes(d, e0, sun);
    CHECK(std::abs(b.s1 - r.s1) < 1e-9);
    CHECK(std::abs(b.s2 - r.s2) < 1e-9);
    CHECK(berry.stokes(d, e0, sun).dolp() <= 0.8 + 1e-12);
    rays.push_back({d.cast<float>(), e0.cast<float>()});
  }
  for (const auto& [batch, scalar] : batch_and_scalar(berry, rays, sun)) {
    CHECK(batch.s1 == Approx(scalar.s1).margin(2e-6));
    CHECK(batch.s2 == Approx(scalar.s2).margin(2e-6));
  }
  CHECK(parse_berry_normalisation("opensky") == BerryNormalisation::opensky);
  CHECK(berry_normalisation_name(BerryNormalisation::split_rayleigh) == "split_rayleigh");
  CHECK_THROWS_WITH(parse_berry_normalisation("bdl"), Catch::Contains("split_rayleigh") && Catch::Contains("opensky"));
}

TEST_CASE("berry parameters out of range are refused", "[berry][bad-input]") {
  CHECK_THROWS_WITH(BerrySky({1.0, -1.0}), Catch::Contains("separation_deg"));
  CHECK_THROWS_WITH(BerrySky({1.0, 60.0}), Catch::Contains("[0, 45]"));
  CHECK_THROWS_WITH(BerrySky({2.0, 10.0}), Catch::Contains("max_dolp"));
}
