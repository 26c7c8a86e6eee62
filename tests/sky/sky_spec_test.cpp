// make_sky: builds only what the spec asks for, and refuses bad fields by name.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "sky/berry.h"
#include "sky/clouds.h"
#include "sky/depolarization.h"
#include "sky/intensity.h"
#include "sky/rayleigh.h"
#include "sky/sky_spec.h"
#include "sky/sun_disc.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using namespace skypol::testing;

namespace {
// The message of the std::invalid_argument that make_sky throws for a spec ("" if none).
std::string error_of(const SkySpec& spec) {
  try {
    make_sky(spec);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("the default spec is a bare Rayleigh sky: nothing else is built", "[sky_spec]") {
  const std::unique_ptr<SkyModel> sky = make_sky({});
  REQUIRE(dynamic_cast<const RayleighSky*>(sky.get()) != nullptr);
  CHECK(sky->name() == "rayleigh");
  SkySpec s;
  s.clouds.seed = 7;  // a seed without coverage is still a clear sky
  CHECK(dynamic_cast<const RayleighSky*>(make_sky(s).get()) != nullptr);
}

TEST_CASE("wrappers appear only for what is asked, clouds outermost", "[sky_spec]") {
  SkySpec s;
  s.model = "berry";
  CHECK(dynamic_cast<const BerrySky*>(make_sky(s).get()) != nullptr);
  s.intensity = "preetham";
  {
    const auto sky = make_sky(s);
    const auto* lit = dynamic_cast<const IntensitySky*>(sky.get());
    REQUIRE(lit != nullptr);
    CHECK(dynamic_cast<const BerrySky*>(&lit->inner()) != nullptr);
    CHECK(sky->name() == "berry");
  }
  s.clouds.coverage = 0.3;
  {
    const auto sky = make_sky(s);
    const auto* cloudy = dynamic_cast<const CloudySky*>(sky.get());
    REQUIRE(cloudy != nullptr);
    CHECK(dynamic_cast<const IntensitySky*>(&cloudy->clear()) != nullptr);
  }
  s.intensity = "rayleigh";
  s.clouds.coverage = 0;
  s.sun_disc = true;
  {
    const auto sky = make_sky(s);
    const auto* disc = dynamic_cast<const SunDiscSky*>(sky.get());
    REQUIRE(disc != nullptr);
    CHECK(dynamic_cast<const BerrySky*>(&disc->inner()) != nullptr);  // no radiance wrapper needed
  }
}

TEST_CASE("berry with zero separation from the factory equals rayleigh", "[sky_spec]") {
  SkySpec b;
  b.model = "berry";
  b.separation_deg = 0;
  b.max_dolp = 0.8;
  SkySpec r;
  r.max_dolp = 0.8;
  const auto berry = make_sky(b), rayleigh = make_sky(r);
  const Sun sun = sun_at(10, 20);
  for (double az = 0; az < 360; az += 40) {
    const Eigen::Vector3d d = enu_direction(az * kRadPerDeg, 30 * kRadPerDeg);
    const Eigen::Vector3d e0 = Eigen::Vector3d::UnitZ().cross(d).normalized();
    const Stokes x = berry->stokes(d, e0, sun), y = rayleigh->stokes(d, e0, sun);
    CHECK(std::abs(x.s1 - y.s1) < 1e-9);
    CHECK(std::abs(x.s2 - y.s2) < 1e-9);
  }
}

TEST_CASE("Pmax from turbidity follows exp(-(T - 0.6)/4)", "[sky_spec][depolarization]") {
  CHECK(max_dolp_from_turbidity(2.0) == Approx(0.7046880897187134));
  CHECK(max_dolp_from_turbidity(6.0) == Approx(0.2592402606458915));
  CHECK(max_dolp_from_turbidity(1.0) < 1.0);
  SkySpec s;
  s.max_dolp_from_turbidity = true;
  s.turbidity = 2.0;
  s.max_dolp = 5.0;  // ignored when Pmax comes from the turbidity
  CHECK(effective_max_dolp(s) == Approx(0.7046880897187134));
  const auto sky = make_sky(s);
  const Sun sun = sun_at(0, 0);
  // 90° from the sun (the zenith for a sun on the horizon) the DoLP is Pmax.
  CHECK(sky->stokes(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), sun).dolp() == Approx(0.7046880897187134));
  CHECK_THROWS_WITH(max_dolp_from_turbidity(-2), Catch::Contains("turbidity"));
}

TEST_CASE("bad fields: std::invalid_argument naming the field and the legal values", "[sky_spec][bad-input]") {
  SkySpec s;
  s.model = "mie";
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.model") && Catch::Contains("rayleigh, berry or vrte"));
  s = {};
  s.intensity = "perez";
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.intensity") && Catch::Contains("uniform, rayleigh or preetham"));
  s = {};
  s.turbidity = -1;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.turbidity") && Catch::Contains("≥ 1"));
  s = {};
  s.intensity = "preetham";
  s.turbidity = 1.5;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.turbidity") && Catch::Contains("[2, 10]"));
  s = {};
  s.max_dolp = 1.2;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.max_dolp") && Catch::Contains("[0, 1]"));
  s = {};
  s.max_dolp = std::nan("");
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.max_dolp"));
  s = {};
  s.model = "berry";  // berry's key: the only model that takes it
  s.separation_deg = 50;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.separation_deg") && Catch::Contains("[0, 45]"));
  s = {};
  s.sun_disc_radiance = -1;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.sun_disc_radiance"));
  s = {};
  s.clouds.coverage = 1.5;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.clouds.coverage") && Catch::Contains("[0, 1]"));
  s = {};
  s.clouds.scale_deg = 0;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.clouds.scale_deg"));
  s = {};
  s.clouds.softness = 0;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.clouds.softness"));
  s = {};
  s.clouds.brightness = 0.2;
  CHECK_THAT(error_of(s), Catch::StartsWith("sky.clouds.brightness"));
  CHECK(error_of(SkySpec{}).empty());
}

TEST_CASE("every configuration keeps the contract at the hard points", "[sky_spec][hard]") {
  // Finite, S0 > 0, 0 ≤ DoLP ≤ 1, S3 = 0, batch = scalar — for each pattern × radiance × clouds ×
  // disc, with the sun at the zenith, on and below the horizon and at the nadir, looking at the
  // zenith, nadir, horizon, sun and anti-sun in odd bases.
  std::vector<Sun> suns = {sun_at(0, 90), sun_at(75, 0), sun_at(200, -8), sun_at(10, -90), sun_at(300, 33)};
  for (const char* model : {"rayleigh", "berry"}) {
    for (const char* intensity : {"uniform", "rayleigh", "preetham"}) {
      for (double coverage : {0.0, 0.5}) {
        for (bool disc : {false, true}) {
          SkySpec spec;
          spec.model = model;
          spec.intensity = intensity;
          spec.clouds.coverage = coverage;
          spec.sun_disc = disc;
          spec.max_dolp = 0.9;
          const auto sky = make_sky(spec);
          for (const Sun& sun : suns) {
            std::vector<Eigen::Vector3d> dirs = {Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ(),
                                                 enu_direction(1.0, 0.0), sun.direction, -sun.direction,
                                                 enu_direction(4.0, -0.2), enu_direction(2.5, 1.2)};
            std::vector<ViewRay> rays;
            std::vector<Stokes> ref;
            for (const Eigen::Vector3d& d : dirs) {
              const Eigen::Vector3d a = std::abs(d.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
              const Eigen::Vector3d e0 = (a - a.dot(d) * d).normalized();
              const Stokes st = sky->stokes(d, e0, sun);
              INFO(model << " " << intensity << " clouds " << coverage << " disc " << disc << " sun el "
                         << sun.elevation / kRadPerDeg << " d " << d.transpose());
              CHECK(std::isfinite(st.s0));
              CHECK(std::isfinite(st.s1));
              CHECK(std::isfinite(st.s2));
              CHECK(st.s0 > 0);
              CHECK(st.s3 == 0.0);
              CHECK(st.dolp() <= 1.0);
              rays.push_back({d.cast<float>(), e0.cast<float>()});
              ref.push_back(st);
            }
            std::vector<StokesF> out(rays.size());
            sky->stokes(rays, sun, out);
            for (std::size_t i = 0; i < rays.size(); ++i) {
              INFO(model << " " << intensity << " clouds " << coverage << " disc " << disc << " ray " << i);
              CHECK(out[i].s0 == Approx(ref[i].s0).epsilon(3e-5));
              CHECK(std::abs(static_cast<double>(out[i].s1) - ref[i].s1) <= 3e-5 * ref[i].s0);
              CHECK(std::abs(static_cast<double>(out[i].s2) - ref[i].s2) <= 3e-5 * ref[i].s0);
            }
          }
        }
      }
    }
  }
}

TEST_CASE("batch throughput of every configuration (informational)", "[.][benchmark]") {
  std::vector<ViewRay> rays;
  for (int i = 0; i < 1 << 16; ++i) {
    const double u = (i + 0.5) / (1 << 16), az = 2.399963 * i;
    const Eigen::Vector3d d(std::sqrt(1 - u * u) * std::sin(az), std::sqrt(1 - u * u) * std::cos(az), u);
    rays.push_back({d.cast<float>(), Eigen::Vector3d::UnitZ().cross(d).normalized().cast<float>()});
  }
  std::vector<StokesF> out(rays.size());
  const Sun sun = sun_at(140, 25);
  struct Config { const char* label; SkySpec spec; };
  SkySpec berry;
  berry.model = "berry";
  SkySpec preetham;
  preetham.intensity = "preetham";
  preetham.sun_disc = true;
  SkySpec cloudy;
  cloudy.clouds.coverage = 0.4;
  for (const Config& c : {Config{"rayleigh", SkySpec{}}, Config{"berry", berry}, Config{"rayleigh+preetham+disc", preetham},
                          Config{"rayleigh+clouds", cloudy}}) {
    const auto sky = make_sky(c.spec);
    const auto t0 = std::chrono::steady_clock::now();
    int reps = 0;
    while (std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(300)) {
      sky->stokes(rays, sun, out);
      ++reps;
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%-24s %7.1f Mrays/s on one core\n", c.label, static_cast<double>(rays.size()) * reps / s / 1e6);
  }
  CHECK(out[0].s0 > 0);
}

TEST_CASE("berry_normalisation: chosen by name, refused by name when unknown", "[sky_spec][berry]") {
  SkySpec s;
  s.model = "berry";
  s.separation_deg = 15;
  CHECK(error_of(s).empty());  // split_rayleigh, the default
  s.berry_normalisation = "opensky";
  CHECK(error_of(s).empty());
  const std::unique_ptr<SkyModel> sky = make_sky(s);
  const auto* berry = dynamic_cast<const BerrySky*>(sky.get());
  REQUIRE(berry != nullptr);
  CHECK(berry->params().normalisation == BerryNormalisation::opensky);
  s.berry_normalisation = "bdl";
  const std::string e = error_of(s);
  CHECK(e.rfind("sky.berry_normalisation: ", 0) == 0);
  CHECK(e.find("\"bdl\"") != std::string::npos);
  CHECK(e.find("split_rayleigh") != std::string::npos);
  CHECK(e.find("opensky") != std::string::npos);
}
