// make_band_skies: the grey models stay one model for every band and never touch a VRTE table; the
// VRTE sky is one model per band whose Stokes vectors differ by wavelength, whose tables are solved
// once and then read from the cache, and whose bad fields are refused by name. Small tables
// (4 streams, grid 8) keep every case to a fraction of a second.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <unistd.h>

#include "sky/vrte/optical_depth.h"
#include "sky/rayleigh.h"
#include "sky/sky_spec.h"
#include "sky/units.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using skypol::testing::sun_at;
using skypol::rad_from_deg;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("skypol-bands-" + std::to_string(::getpid()) + "-" + name)) {
    fs::remove_all(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::size_t files() const {
    if (!fs::exists(path)) return 0;
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(path)) ++n;
    return n;
  }
};

SkySpec small_vrte() {
  SkySpec s;
  s.model = "vrte";
  s.streams = 4;
  s.grid = 8;
  s.aerosol.type = "continental_average";
  s.aerosol.tau_550 = 0.2;
  s.aerosol.angle_nodes = 64;
  return s;
}

std::string message_of(const SkySpec& spec) {
  try {
    validate(spec);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

const std::vector<std::string> kRgb{"R", "G", "B"};

}  // namespace

TEST_CASE("a grey sky is one model for every band and builds no table", "[band_skies]") {
  TempDir cache("grey");
  SkySpec s;  // rayleigh
  const BandSkies b = make_band_skies(s, kRgb, SiteAtmosphere{}, cache.path);
  REQUIRE(b.skies.size() == 1);
  CHECK(dynamic_cast<const RayleighSky*>(b.skies.front().get()) != nullptr);
  CHECK(&b.band(0) == &b.band(2));
  CHECK(b.tables_built == 0);
  CHECK(b.tables_read == 0);
  CHECK(cache.files() == 0);  // the cache folder is not even created
  s.model = "berry";
  CHECK(make_band_skies(s, kRgb, SiteAtmosphere{}, cache.path).skies.size() == 1);
  CHECK(cache.files() == 0);
}

TEST_CASE("vrte is one model per band, and its bands differ as the sky's colours do", "[band_skies]") {
  TempDir cache("rgb");
  const BandSkies b = make_band_skies(small_vrte(), kRgb, SiteAtmosphere{}, cache.path);
  REQUIRE(b.skies.size() == 3);
  CHECK(b.tables_built == 3);
  CHECK(b.band(0).name() == "vrte");
  const Sun sun = sun_at(135, 30);
  // The zenith and a view 90° from the sun in its vertical, on the anti-sun side: the blue band is
  // brighter than the green, the green than the red (τ_R ∝ ~λ⁻⁴ dominates this thin atmosphere).
  const Eigen::Vector3d views[] = {Eigen::Vector3d(0, 0, 1),
                                   enu_direction(rad_from_deg(135.0 + 180.0), rad_from_deg(60))};
  for (const Eigen::Vector3d& d : views) {
    Eigen::Vector3d e0 = Eigen::Vector3d::UnitX().cross(d);
    if (e0.norm() < 1e-9) e0 = Eigen::Vector3d::UnitY();
    e0.normalize();
    const Stokes r = b.band(0).stokes(d, e0, sun), g = b.band(1).stokes(d, e0, sun), bl = b.band(2).stokes(d, e0, sun);
    INFO("d = " << d.transpose());
    CHECK(bl.s0 > g.s0);
    CHECK(g.s0 > r.s0);
    CHECK(r.s1 != g.s1);
    CHECK(g.s2 != bl.s2);
    for (const Stokes& s : {r, g, bl}) CHECK((std::isfinite(s.s0) && std::isfinite(s.s1) && std::isfinite(s.s2)));
  }
}

TEST_CASE("vrte tables are solved once, then read from the cache", "[band_skies]") {
  TempDir cache("warm");
  const std::vector<std::string> y{"Y"};
  const BandSkies cold = make_band_skies(small_vrte(), y, SiteAtmosphere{}, cache.path);
  CHECK(cold.tables_built == 1);
  CHECK(cold.tables_read == 0);
  CHECK(cache.files() == 1);
  const BandSkies warm = make_band_skies(small_vrte(), y, SiteAtmosphere{}, cache.path);
  CHECK(warm.tables_built == 0);
  CHECK(warm.tables_read == 1);
  CHECK(cache.files() == 1);
  const Sun sun = sun_at(200, 40);
  const Eigen::Vector3d d = enu_direction(0.3, 0.9), e0 = Eigen::Vector3d::UnitZ().cross(d).normalized();
  const Stokes a = cold.band(0).stokes(d, e0, sun), b = warm.band(0).stokes(d, e0, sun);
  CHECK(a.s0 == b.s0);
  CHECK(a.s1 == b.s1);
  CHECK(a.s2 == b.s2);
  // Anything that changes the optics is another table: the site's pressure, the aerosol load.
  SiteAtmosphere high;
  high.pressure_hpa = 800;
  CHECK(make_band_skies(small_vrte(), y, high, cache.path).tables_built == 1);
  SkySpec more = small_vrte();
  more.aerosol.tau_550 = 0.4;
  CHECK(make_band_skies(more, y, SiteAtmosphere{}, cache.path).tables_built == 1);
  CHECK(cache.files() == 3);
}

TEST_CASE("vrte at the hard cases is finite", "[band_skies]") {
  const std::vector<std::string> y{"Y"};
  const BandSkies b = make_band_skies(small_vrte(), y, SiteAtmosphere{}, {});
  CHECK(b.tables_built == 1);
  for (const double el : {90.0, 0.0, 0.01, -5.0}) {
    const Sun sun = sun_at(75, el);
    for (const double vel : {90.0, 45.0, 0.0, -0.0, -30.0, -90.0}) {
      for (const double vaz : {0.0, 75.0, 255.0}) {
        const Eigen::Vector3d d = enu_direction(rad_from_deg(vaz), rad_from_deg(vel));
        Eigen::Vector3d e0 = Eigen::Vector3d::UnitZ().cross(d);
        if (e0.norm() < 1e-9) e0 = Eigen::Vector3d::UnitX();
        const Stokes s = b.band(0).stokes(d, e0.normalized(), sun);
        INFO("sun el " << el << ", view el " << vel << " az " << vaz << ": " << s.s0 << " " << s.s1 << " " << s.s2);
        CHECK((std::isfinite(s.s0) && std::isfinite(s.s1) && std::isfinite(s.s2) && s.s0 >= 0));
      }
    }
  }
}

TEST_CASE("band wavelengths come from the band names or from the spec", "[band_skies]") {
  SkySpec s = small_vrte();
  CHECK(band_wavelengths_nm(s, kRgb) == std::vector<double>{610, 530, 465});
  s.wavelengths_nm = {450, 550, 650};
  CHECK(band_wavelengths_nm(s, kRgb) == std::vector<double>{450, 550, 650});
  s.wavelengths_nm = {450};
  CHECK_THROWS_WITH(band_wavelengths_nm(s, kRgb), Catch::StartsWith("sky.wavelengths_nm: gives 1 wavelength(s) for 3"));
  s.wavelengths_nm.clear();
  const std::vector<std::string> odd{"NIR"};
  CHECK_THROWS_WITH(band_wavelengths_nm(s, odd), Catch::StartsWith("sky.wavelengths_nm: band \"NIR\""));
}

TEST_CASE("vrte fields are refused by name", "[band_skies]") {
  SkySpec s = small_vrte();
  CHECK(message_of(s).empty());
  s.ground_albedo = 1.5;
  CHECK_THAT(message_of(s), Catch::StartsWith("sky.ground_albedo: 1.5 is outside [0, 1]"));
  s = small_vrte();
  s.streams = 2;
  CHECK_THAT(message_of(s), Catch::StartsWith("sky.streams: 2"));
  s = small_vrte();
  s.grid = 4;
  CHECK_THAT(message_of(s), Catch::StartsWith("sky.grid: 4"));
  s = small_vrte();
  s.aerosol.tau_550 = -1;
  CHECK_THAT(message_of(s), Catch::StartsWith("sky.aerosol.tau_550:"));
  s = small_vrte();
  s.aerosol.type = "volcanic";
  CHECK_THAT(message_of(s), Catch::StartsWith("sky.aerosol.type:"));
  s = small_vrte();
  s.wavelengths_nm = {100};
  CHECK_THAT(message_of(s), Catch::StartsWith("sky.wavelengths_nm: 100"));
  // make_sky builds grey models only: vrte needs its bands.
  CHECK_THROWS_WITH(make_sky(small_vrte()), Catch::StartsWith("sky.model: vrte is one model per band"));
}

TEST_CASE("the table cache folder follows SKYPOL_CACHE_DIR, then XDG_CACHE_HOME, then HOME", "[band_skies]") {
  const char* keep[] = {std::getenv("SKYPOL_CACHE_DIR"), std::getenv("XDG_CACHE_HOME"), std::getenv("HOME")};
  const std::string saved[] = {keep[0] ? keep[0] : "", keep[1] ? keep[1] : "", keep[2] ? keep[2] : ""};
  ::setenv("SKYPOL_CACHE_DIR", "/tmp/a", 1);
  ::setenv("XDG_CACHE_HOME", "/tmp/b", 1);
  ::setenv("HOME", "/tmp/c", 1);
  CHECK(default_table_cache_dir() == fs::path("/tmp/a"));
  ::unsetenv("SKYPOL_CACHE_DIR");
  CHECK(default_table_cache_dir() == fs::path("/tmp/b/skypol"));
  ::unsetenv("XDG_CACHE_HOME");
  CHECK(default_table_cache_dir() == fs::path("/tmp/c/.cache/skypol"));
  const char* names[] = {"SKYPOL_CACHE_DIR", "XDG_CACHE_HOME", "HOME"};
  for (int i = 0; i < 3; ++i) {
    if (keep[i]) {
      ::setenv(names[i], saved[i].c_str(), 1);
    } else {
      ::unsetenv(names[i]);
    }
  }
}
