// The VRTE sky (sky/vrte/vrte_sky.h) against skypol's other models and the physics of the real sky:
// in the thin-atmosphere limit its DoLP and AoLP are the single-scattering Rayleigh pattern
// (RayleighSky: the AoLP agreement is the test of the solver's Q/U signs); with a realistic
// optical depth the Arago, Babinet and Brewster neutral points appear on the sun's vertical at
// the distances observed and computed since Coulson (1988); the hard cases stay finite.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "sky/rayleigh.h"
#include "sky/vrte/vrte_sky.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using namespace skypol::testing;

namespace {

std::shared_ptr<const vrte::VrteTable> rayleigh_table(double tau, double rho, double albedo, int grid = 25) {
  LayerOptics o;
  o.tau_rayleigh = tau;
  o.depolarization = rho;
  vrte::TableOptions opt;
  opt.grid = grid;
  return std::make_shared<const vrte::VrteTable>(vrte::VrteTable::build(o, albedo, opt));
}

// Molecules (τ 0.1) with a polarizing, forward-scattering aerosol: 24 Fourier terms, an aureole in
// the exact single scattering.
std::shared_ptr<const vrte::VrteTable> hazy_table() {
  LayerOptics o;
  o.tau_rayleigh = 0.1;
  o.depolarization = 0.0279;
  o.tau_aerosol = 0.2;
  o.aerosol_ssa = 0.95;
  o.aerosol = vrte::synthetic_aerosol(0.7, 200, 0.2, 0.05);
  return std::make_shared<const vrte::VrteTable>(vrte::VrteTable::build(o, 0.1, {}));
}

// The local-meridian basis: e0 towards the zenith along the meridian (North at the zenith).
Eigen::Vector3d meridian_e0(const Eigen::Vector3d& d) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ() - d.z() * d;
  if (up.norm() < 1e-12) return Eigen::Vector3d::UnitY();
  return up.normalized();
}

// S1 in the meridian basis along the sun's vertical, at angle `a_deg` from the sun measured
// over the zenith (0 = the sun, 180 = the anti-sun). S2 vanishes there by symmetry; S1 < 0 is
// the Rayleigh sense (E horizontal, ⟂ the vertical), S1 > 0 the reversed sense between a
// neutral point and the sun or anti-sun.
Stokes on_vertical(const VrteSky& sky, const Sun& sun, double a_deg) {
  const double el = sun.elevation / kRadPerDeg + a_deg;  // elevation past 90 continues over the zenith
  const double az = el <= 90 ? sun.azimuth / kRadPerDeg : sun.azimuth / kRadPerDeg + 180;
  const double e = el <= 90 ? el : 180 - el;
  const Eigen::Vector3d d = enu_direction(az * kRadPerDeg, e * kRadPerDeg);
  return sky.stokes(d, meridian_e0(d), sun);
}

// The angle from the sun (over the zenith) where S1 changes sign, searched in [lo, hi] degrees.
std::optional<double> sign_change(const VrteSky& sky, const Sun& sun, double lo, double hi) {
  double prev = on_vertical(sky, sun, lo).s1;
  for (double a = lo + 0.05; a <= hi; a += 0.05) {
    const double cur = on_vertical(sky, sun, a).s1;
    if ((prev < 0) != (cur < 0)) return a;
    prev = cur;
  }
  return std::nullopt;
}

}  // namespace

TEST_CASE("Thin atmosphere: DoLP and AoLP are RayleighSky's, radiance the closed-form single scattering",
          "[vrte][sky]") {
  const double tau = 1e-4;
  const VrteSky sky(rayleigh_table(tau, 0.0, 0.0));
  const RayleighSky ray;
  std::mt19937_64 rng(7);
  for (double sun_el : {5.0, 30.0, 60.0, 89.0}) {
    const Sun sun = sun_at(40.0, sun_el);
    for (int k = 0; k < 300; ++k) {
      Eigen::Vector3d d = random_unit(rng);
      if (d.z() < 0.05) continue;  // above ~3°: below, the slant path is no longer thin
      const Eigen::Vector3d e0 = random_perpendicular(d, rng);
      const Stokes v = sky.stokes(d, e0, sun), r = ray.stokes(d, e0, sun);
      INFO("sun el " << sun_el << " d " << d.transpose());
      CHECK(v.dolp() == Approx(r.dolp()).margin(5e-4));
      // Near the sun and anti-sun (DoLP → 0) the angle of a weak polarization is undefined.
      if (r.dolp() > 0.2) CHECK(std::abs(axial_diff(v.aolp(), r.aolp())) < 0.03 * kRadPerDeg);
      // I/F = (3/4)(1 + cos²γ)/(4π) · μ0 (e^{−τ/μ} − e^{−τ/μ0})/(μ − μ0)  (single scattering of a thin layer)
      const double mu = d.z(), mu0 = sun.direction.z(), c = d.dot(sun.direction);
      const double f = std::abs(mu - mu0) < 1e-9 ? tau / mu0 * std::exp(-tau / mu0)
                                                 : mu0 * (std::exp(-tau / mu) - std::exp(-tau / mu0)) / (mu - mu0);
      CHECK(v.s0 == Approx(0.75 * (1 + c * c) / (4 * kPi) * f).epsilon(2e-3));
    }
  }
}

TEST_CASE("Neutral points: Babinet, Brewster and Arago on the sun's vertical for tau 0.1 and 0.25", "[vrte][sky]") {
  // Molecular atmosphere with the depolarization of air (ρ = 0.0279, Young 1980) and a dark
  // ground. Observed and computed distances from the sun / anti-sun are 10°–30° and grow with τ
  // (Coulson 1988, ch. 5; Horváth et al. 2002).
  double arago_prev = 0, babinet_prev = 0, brewster_prev = 0;
  for (double tau : {0.1, 0.25}) {
    const VrteSky sky(rayleigh_table(tau, 0.0279, 0.0));
    const Sun low = sun_at(120.0, 10.0);
    const auto babinet = sign_change(sky, low, 1.0, 60.0);
    const auto arago = sign_change(sky, low, 120.0, 179.0);  // between the zenith side and the anti-sun
    const Sun high = sun_at(120.0, 60.0);
    const auto brewster = sign_change(sky, high, -59.0, -1.0);
    REQUIRE(babinet);
    REQUIRE(arago);
    REQUIRE(brewster);
    const double d_babinet = *babinet, d_arago = 180.0 - *arago, d_brewster = -*brewster;
    std::printf(
        "tau %.2f: Babinet %.1f deg above the sun, Arago %.1f deg above the anti-sun, Brewster %.1f deg below the "
        "sun\n",
        tau, d_babinet, d_arago, d_brewster);
    for (double dist : {d_babinet, d_arago, d_brewster}) {
      CHECK(dist > 5.0);
      CHECK(dist < 35.0);
    }
    CHECK(d_babinet > babinet_prev);
    CHECK(d_arago > arago_prev);
    CHECK(d_brewster > brewster_prev);
    babinet_prev = d_babinet, arago_prev = d_arago, brewster_prev = d_brewster;
    // Between the neutral points the polarization is Rayleigh's (E horizontal): S1 < 0 at 90°.
    CHECK(on_vertical(sky, low, 90.0).s1 < 0);
  }
}

TEST_CASE("Hard cases: sun at the zenith and at the horizon, views at the horizon, zenith and below", "[vrte][sky]") {
  const VrteSky sky(rayleigh_table(0.25, 0.0279, 0.3));
  std::mt19937_64 rng(3);
  for (double sun_el : {90.0, 89.999, 45.0, 0.5, 0.01, 0.0, -0.01, -30.0, -90.0}) {
    const Sun sun = sun_at(10.0, sun_el);
    std::vector<Eigen::Vector3d> views{Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ(), sun.direction,
                                       -sun.direction,           enu_direction(0.3, 0.0),   enu_direction(2.0, 1e-9),
                                       enu_direction(4.0, -1e-9)};
    for (int k = 0; k < 50; ++k) views.push_back(random_unit(rng));
    for (const auto& d : views) {
      const Stokes s = sky.stokes(d, perpendicular(d), sun);
      INFO("sun el " << sun_el << " d " << d.transpose());
      CHECK(std::isfinite(s.s0));
      CHECK(std::isfinite(s.s1));
      CHECK(std::isfinite(s.s2));
      CHECK(s.s0 >= 0.0);
      CHECK(s.dolp() <= 1.0);
      if (sun_el <= 0.0) CHECK(s.s0 == 0.0);
      if (d.z() < 0.0 && sun_el > 0.0) {
        CHECK(s.s0 > 0.0);  // the lit ground, unpolarized
        CHECK(s.s1 == 0.0);
      }
    }
  }
  // Sun at the zenith: the sky is symmetric about it; the E-vector is horizontal everywhere
  // (⟂ the vertical through the sun), and the same at every azimuth.
  const Sun top = sun_at(0.0, 90.0);
  const Eigen::Vector3d a = enu_direction(0.2, 40 * kRadPerDeg), b = enu_direction(2.9, 40 * kRadPerDeg);
  const Stokes sa = sky.stokes(a, meridian_e0(a), top), sb = sky.stokes(b, meridian_e0(b), top);
  CHECK(sa.s0 == Approx(sb.s0).epsilon(1e-9));
  CHECK(sa.s1 == Approx(sb.s1).epsilon(1e-9));
  CHECK(sa.s1 < 0.0);
  CHECK(std::abs(sa.s2) < 1e-9 * sa.s0);
  // The view at the zenith does not depend on the basis' azimuth other than by the rotation.
  const Sun sun = sun_at(30.0, 40.0);
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Stokes s1 = sky.stokes(z, Eigen::Vector3d::UnitX(), sun);
  const Stokes s2 = sky.stokes(z, Eigen::Vector3d::UnitY(), sun);
  CHECK(s2.s1 == Approx(-s1.s1).margin(1e-12));
  CHECK(s2.s2 == Approx(-s1.s2).margin(1e-12));
}

namespace {

// The worst difference of the batch path (per-sun plan, float) from the scalar path (the table
// evaluated in double), as a fraction of the scalar S0 (s0) and, for the polarized radiance,
// of the brightest sky of the sample (p; p_sun within 0.5° of the sun). Within a few hundredths
// of a degree of the sun the two paths' single scattering differs by design: the scalar path
// multiplies the tabulated F12 at Θ → 0 (not 0 for a table whose first node is not the forward
// direction) by the rotation out of an ill-defined scattering plane; the batch path takes the
// polarized part along d × s, which vanishes there.
struct PathDifference {
  double s0 = 0, p = 0, p_sun = 0;
};

PathDifference batch_against_scalar(const VrteSky& sky, const Sun& sun, std::span<const ViewRay> rays) {
  struct Pair {
    ViewRay ray;
    StokesF batch;
    Stokes scalar;
  };
  std::vector<Pair> both;
  {
    const auto pairs = batch_and_scalar(sky, rays, sun);
    for (std::size_t i = 0; i < rays.size(); ++i) both.push_back({rays[i], pairs[i].batch, pairs[i].scalar});
  }
  double brightest = 0;
  for (const auto& b : both) brightest = std::max(brightest, b.scalar.s0);
  PathDifference d;
  for (const auto& b : both) {
    REQUIRE(std::isfinite(b.batch.s0));
    REQUIRE(std::isfinite(b.batch.s1));
    REQUIRE(std::isfinite(b.batch.s2));
    CHECK(b.batch.s3 == 0.0f);
    const double s0 = b.batch.s0, s1 = b.batch.s1, s2 = b.batch.s2;
    if (b.scalar.s0 > 0) d.s0 = std::max(d.s0, std::abs(s0 - b.scalar.s0) / b.scalar.s0);
    else CHECK(s0 == 0.0);
    const double dp = std::hypot(s1 - b.scalar.s1, s2 - b.scalar.s2) / brightest;
    const bool near_sun = b.ray.d.cast<double>().dot(sun.direction) > std::cos(0.5 * kRadPerDeg);
    if (brightest > 0) (near_sun ? d.p_sun : d.p) = std::max(near_sun ? d.p_sun : d.p, dp);
  }
  return d;
}

std::vector<ViewRay> sample_rays(const Sun& sun, int n) {
  std::mt19937_64 rng(11);
  std::vector<ViewRay> rays;
  auto add = [&](const Eigen::Vector3d& d) { rays.push_back({d.cast<float>(), random_perpendicular(d, rng).cast<float>()}); };
  for (int k = 0; k < n; ++k) add(random_unit(rng));
  // The zenith, the horizon, the sun and its aureole, the anti-solar vertical.
  add(Eigen::Vector3d::UnitZ());
  for (double az = 0; az < 360; az += 30) add(enu_direction(az * kRadPerDeg, 0.0));
  add(sun.direction);
  for (double off : {0.05, 0.3, 1.0, 3.0}) {
    add(enu_direction(sun.azimuth, std::min(sun.elevation + off * kRadPerDeg, kPi / 2)));
    add(enu_direction(sun.azimuth + off * kRadPerDeg, sun.elevation));
  }
  for (double el = 1; el < 90; el += 7) add(enu_direction(sun.azimuth + kPi, el * kRadPerDeg));
  return rays;
}

}  // namespace

TEST_CASE("The batch path (one plan per sun, float) agrees with the scalar path (the table in double)",
          "[vrte][sky]") {
  // Molecules alone (3 Fourier terms) and molecules with a polarizing, forward-scattering aerosol
  // (24 terms, an aureole in the exact single scattering), for suns from the horizon to the zenith.
  const VrteSky clear(rayleigh_table(0.1, 0.0279, 0.1)), hazy(hazy_table());
  PathDifference worst;
  for (const VrteSky* sky : {&clear, &hazy})
    for (double el : {1.0, 5.0, 35.0, 70.0, 90.0}) {
      const Sun sun = sun_at(200.0, el);
      const std::vector<ViewRay> rays = sample_rays(sun, 2000);
      const PathDifference d = batch_against_scalar(*sky, sun, rays);
      INFO((sky == &clear ? "clear" : "hazy") << " sun elevation " << el);
      CHECK(d.s0 < 2e-5);
      CHECK(d.p < 2e-6);
      CHECK(d.p_sun < 2e-5);
      worst.s0 = std::max(worst.s0, d.s0);
      worst.p = std::max(worst.p, d.p);
      worst.p_sun = std::max(worst.p_sun, d.p_sun);
    }
  std::printf("batch path against the scalar path: S0 within %.2e of S0, polarization within %.2e of the brightest"
              " (%.2e within 0.5 deg of the sun)\n",
              worst.s0, worst.p, worst.p_sun);
  // Frames alternate suns: each call answers for its own sun.
  const Sun a = sun_at(120.0, 20.0), b = sun_at(250.0, 50.0);
  const std::vector<ViewRay> rays = sample_rays(a, 200);
  for (const Sun* sun : {&a, &b, &a}) {
    const PathDifference d = batch_against_scalar(hazy, *sun, rays);
    CHECK(d.s0 < 2e-5);
    CHECK(d.p < 2e-6);
  }
  // A ray of NaNs (a renderer's unseen pixel, say) reads inside the plan and gives a finite 0.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<ViewRay> bad{{{nan, nan, nan}, {nan, nan, nan}}, {{nan, 0.0f, 1.0f}, {1.0f, 0.0f, nan}}};
  std::vector<StokesF> bad_out(bad.size());
  hazy.stokes(bad, a, bad_out);
  for (const StokesF& r : bad_out) {
    CHECK(r.s0 == 0.0f);
    CHECK(r.s1 == 0.0f);
    CHECK(r.s2 == 0.0f);
  }
  // A sun below the horizon lights nothing, in both paths.
  const auto night = batch_and_scalar(hazy, rays, sun_at(0.0, -2.0));
  for (const auto& n : night) {
    CHECK(n.batch.s0 == 0.0f);
    CHECK(n.batch.s1 == 0.0f);
    CHECK(n.scalar.s0 == 0.0);
  }
}

TEST_CASE("The structure-of-arrays path gives the ViewRay path's floats", "[vrte][sky]") {
  const VrteSky sky(rayleigh_table(0.1, 0.0279, 0.1));
  const Sun sun = sun_at(200.0, 35.0);
  const std::vector<ViewRay> rays = sample_rays(sun, 500);
  std::vector<StokesF> batch(rays.size());
  sky.stokes(rays, sun, batch);
  std::vector<float> dx, dy, dz, ux, uy, uz;
  for (const auto& r : rays) {
    dx.push_back(r.d.x()), dy.push_back(r.d.y()), dz.push_back(r.d.z());
    ux.push_back(r.e0.x()), uy.push_back(r.e0.y()), uz.push_back(r.e0.z());
  }
  std::vector<float> s0(rays.size()), s1(rays.size()), s2(rays.size()), s3(rays.size());
  sky.stokes_soa({rays.size(), dx.data(), dy.data(), dz.data(), ux.data(), uy.data(), uz.data()}, sun,
                 {s0.data(), s1.data(), s2.data(), s3.data()});
  for (std::size_t i = 0; i < rays.size(); ++i) {
    CHECK(s0[i] == batch[i].s0);
    CHECK(s1[i] == batch[i].s1);
    CHECK(s2[i] == batch[i].s2);
    CHECK(s3[i] == batch[i].s3);
  }
}

TEST_CASE("Bands evaluated together give each band's own floats; other model sets are declined untouched",
          "[vrte][sky]") {
  // Three bands as a colour scene has them: molecules at two depths and molecules with aerosol
  // (24 Fourier terms against 3), all on the default grid.
  const VrteSky red(rayleigh_table(0.05, 0.0279, 0.1)), green(rayleigh_table(0.1, 0.0279, 0.1)), blue(hazy_table());
  const SkyModel* bands[] = {&red, &green, &blue};
  const Sun sun = sun_at(200.0, 35.0);
  const std::vector<ViewRay> rays = sample_rays(sun, 500);
  const std::size_t n = rays.size();
  std::vector<float> in(6 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      in[static_cast<std::size_t>(c) * n + i] = rays[i].d[c];
      in[static_cast<std::size_t>(3 + c) * n + i] = rays[i].e0[c];
    }
  const ViewRaysSoA soa{n, &in[0], &in[n], &in[2 * n], &in[3 * n], &in[4 * n], &in[5 * n]};
  std::vector<float> together(12 * n, -7.0f), alone(12 * n, -7.0f);
  auto planes = [n](std::vector<float>& v, std::size_t b) {
    return StokesSoA{&v[4 * b * n], &v[(4 * b + 1) * n], &v[(4 * b + 2) * n], &v[(4 * b + 3) * n]};
  };
  const StokesSoA out[] = {planes(together, 0), planes(together, 1), planes(together, 2)};
  for (const Sun& s : {sun, sun_at(40.0, 80.0), sun_at(0.0, -2.0)}) {
    REQUIRE(VrteSky::stokes_soa_bands(bands, soa, s, out));
    for (std::size_t b = 0; b < 3; ++b) bands[b]->stokes_soa(soa, s, planes(alone, b));
    CHECK(together == alone);
  }
  CHECK(std::all_of(together.begin(), together.end(), [](float x) { return x == 0.0f; }));  // the last sun: night
  // Declined, nothing written: one band, a model that is not VrteSky, a table on another grid,
  // too few outputs.
  std::fill(together.begin(), together.end(), -7.0f);
  const RayleighSky grey;
  const VrteSky coarse(rayleigh_table(0.1, 0.0279, 0.1, 17));
  const SkyModel* one[] = {&red};
  const SkyModel* mixed[] = {&red, &grey};
  const SkyModel* grids[] = {&red, &coarse};
  CHECK_FALSE(VrteSky::stokes_soa_bands(one, soa, sun, std::span(out).first(1)));
  CHECK_FALSE(VrteSky::stokes_soa_bands(mixed, soa, sun, std::span(out).first(2)));
  CHECK_FALSE(VrteSky::stokes_soa_bands(grids, soa, sun, std::span(out).first(2)));
  CHECK_FALSE(VrteSky::stokes_soa_bands(bands, soa, sun, std::span(out).first(2)));
  CHECK(std::all_of(together.begin(), together.end(), [](float x) { return x == -7.0f; }));
}

TEST_CASE("Aerosol: a bright aureole round the sun and less polarization 90 degrees from it", "[vrte][sky]") {
  // A forward-scattering, weakly polarizing aerosol (Henyey–Greenstein g = 0.7) added to the
  // molecules: the sky near the sun brightens many times over, and the maximum DoLP drops
  // (aerosols depolarize the real sky: Coulson 1988; Horváth et al. 2002).
  LayerOptics o;
  o.tau_rayleigh = 0.1;
  o.depolarization = 0.0279;
  o.tau_aerosol = 0.3;
  o.aerosol_ssa = 0.95;
  for (int i = 0; i <= 400; ++i) {
    const double x = -1.0 + 2.0 * i / 400.0, g = 0.7;
    const double f = (1 - g * g) / std::pow(1 + g * g - 2 * g * x, 1.5);
    o.aerosol.cos_theta.push_back(x);
    o.aerosol.f11.push_back(f);
    o.aerosol.f12.push_back(-0.1 * f * (1 - x * x));
    o.aerosol.f22.push_back(f);
    o.aerosol.f33.push_back(f * x);
    o.aerosol.f34.push_back(0.0);
    o.aerosol.f44.push_back(f * x);
  }
  const VrteSky hazy(std::make_shared<const vrte::VrteTable>(vrte::VrteTable::build(o, 0.1, {})));
  const VrteSky clear(rayleigh_table(0.1, 0.0279, 0.1));
  const Sun sun = sun_at(0.0, 40.0);
  auto at = [&](const VrteSky& sky, double az_deg, double el_deg) {
    const Eigen::Vector3d d = enu_direction(az_deg * kRadPerDeg, el_deg * kRadPerDeg);
    return sky.stokes(d, meridian_e0(d), sun);
  };
  // 5° above the sun against 90° away on the solar vertical's far side, at the zenith's other side.
  const double aureole_hazy = at(hazy, 0, 45).s0 / at(hazy, 180, 40).s0;
  const double aureole_clear = at(clear, 0, 45).s0 / at(clear, 180, 40).s0;
  CHECK(aureole_hazy > 3 * aureole_clear);
  double max_hazy = 0, max_clear = 0;
  for (double a = 0; a < 360; a += 5) {
    // The circle 90° from the sun: where Rayleigh polarization peaks.
    const Eigen::Vector3d s = sun.direction;
    const Eigen::Vector3d u = Eigen::Vector3d::UnitZ().cross(s).normalized(), v = s.cross(u);
    const Eigen::Vector3d d = std::cos(a * kRadPerDeg) * u + std::sin(a * kRadPerDeg) * v;
    if (d.z() < 0.1) continue;
    max_hazy = std::max(max_hazy, hazy.stokes(d, meridian_e0(d), sun).dolp());
    max_clear = std::max(max_clear, clear.stokes(d, meridian_e0(d), sun).dolp());
  }
  CHECK(max_clear > 0.75);
  CHECK(max_hazy < max_clear - 0.1);
  std::printf("max DoLP 90 deg from the sun: clear %.3f, hazy %.3f; aureole ratio clear %.2f, hazy %.2f\n", max_clear,
              max_hazy, aureole_clear, aureole_hazy);
}
