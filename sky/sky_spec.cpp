#include "sky/sky_spec.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sky/berry.h"
#include "sky/depolarization.h"
#include "sky/intensity.h"
#include "sky/optical_depth.h"
#include "sky/spec_errors.h"
#include "sky/rayleigh.h"
#include "sky/sun_disc.h"
#include "sky/vrte_sky.h"
#include "sky/vrte_table.h"

namespace skypol::sky {
namespace {

// The field names below are relative to "sky" (sky/spec_errors.h words the message).
[[noreturn]] void bad(const std::string& field, const std::string& message) { spec_error("sky." + field, message); }

void check_range(const std::string& field, double v, double lo, double hi, const std::string& why = "") {
  if (!(v >= lo && v <= hi)) {
    bad(field, spec_number(v) + " is outside [" + spec_number(lo) + ", " + spec_number(hi) + "]" + (why.empty() ? "" : " (" + why + ")"));
  }
}

}  // namespace

void validate(const SkySpec& s) {
  if (s.model != "rayleigh" && s.model != "berry" && s.model != "vrte") {
    bad("model", "\"" + s.model + "\" is unknown (expected rayleigh, berry or vrte)");
  }
  if (s.intensity != "uniform" && s.intensity != "rayleigh" && s.intensity != "preetham") {
    bad("intensity", "\"" + s.intensity + "\" is unknown (expected uniform, rayleigh or preetham)");
  }
  if (!(std::isfinite(s.turbidity) && s.turbidity >= 1.0)) {
    bad("turbidity", spec_number(s.turbidity) + " must be ≥ 1 (1 = a pure molecular atmosphere)");
  }
  if (s.intensity == "preetham") check_range("turbidity", s.turbidity, 2.0, 10.0, "Preetham's fit");
  if (!s.max_dolp_from_turbidity) check_range("max_dolp", s.max_dolp, 0.0, 1.0);
  check_range("separation_deg", s.separation_deg, 0.0, 45.0);
  if (s.berry_normalisation != "split_rayleigh" && s.berry_normalisation != "opensky") {
    bad("berry_normalisation",
        "\"" + s.berry_normalisation + "\" is unknown (expected split_rayleigh or opensky)");
  }
  if (!(std::isfinite(s.sun_disc_radiance) && s.sun_disc_radiance >= 0.0)) {
    bad("sun_disc_radiance", spec_number(s.sun_disc_radiance) + " must be ≥ 0");
  }
  check_range("clouds.coverage", s.clouds.coverage, 0.0, 1.0);
  check_range("clouds.scale_deg", s.clouds.scale_deg, 1.0, 90.0);
  if (!(s.clouds.softness > 0.0 && s.clouds.softness <= 1.0)) {
    bad("clouds.softness", spec_number(s.clouds.softness) + " is outside (0, 1]");
  }
  if (!(std::isfinite(s.clouds.brightness) && s.clouds.brightness >= 1.0)) {
    bad("clouds.brightness", spec_number(s.clouds.brightness) + " must be ≥ 1 (cloud is brighter than the sky behind it)");
  }
  if (s.model != "vrte") return;
  validate(s.aerosol);  // "sky.aerosol.<field>: …"
  check_range("ground_albedo", s.ground_albedo, 0.0, 1.0);
  if (!(s.streams >= 4 && s.streams <= 64)) bad("streams", std::to_string(s.streams) + " is outside [4, 64]");
  if (!(s.grid >= 8 && s.grid <= 129)) bad("grid", std::to_string(s.grid) + " is outside [8, 129]");
  for (double w : s.wavelengths_nm) check_range("wavelengths_nm", w, 200.0, 4000.0, "nm, Bodhaine's formula");
}

double effective_max_dolp(const SkySpec& spec) {
  return spec.max_dolp_from_turbidity ? max_dolp_from_turbidity(spec.turbidity) : spec.max_dolp;
}

namespace {

// The wrappers every model takes: a different radiance (grey models only), clouds, the sun's disc.
std::unique_ptr<SkyModel> wrap(std::unique_ptr<SkyModel> sky, const SkySpec& spec) {
  if (spec.clouds.coverage > 0.0) sky = std::make_unique<CloudySky>(std::move(sky), spec.clouds);
  if (spec.sun_disc) sky = std::make_unique<SunDiscSky>(std::move(sky), spec.sun_disc_radiance);  // over clouds
  return sky;
}

}  // namespace

std::vector<double> band_wavelengths_nm(const SkySpec& spec, std::span<const std::string> bands) {
  if (!spec.wavelengths_nm.empty()) {
    if (spec.wavelengths_nm.size() != bands.size()) {
      bad("wavelengths_nm", "gives " + std::to_string(spec.wavelengths_nm.size()) + " wavelength(s) for " +
                                std::to_string(bands.size()) + " band(s): one per band, in the bands' order");
    }
    return spec.wavelengths_nm;
  }
  std::vector<double> out;
  for (const std::string& b : bands) {
    try {
      out.push_back(band_wavelength_nm(b));
    } catch (const std::invalid_argument&) {
      bad("wavelengths_nm", "band \"" + b + "\" has no built-in wavelength (R, G, B, Y have): give one per band");
    }
  }
  return out;
}

std::filesystem::path default_table_cache_dir() {
  if (const char* d = std::getenv("SKYPOL_CACHE_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::filesystem::path(x) / "skypol";
  if (const char* h = std::getenv("HOME"); h && *h) return std::filesystem::path(h) / ".cache" / "skypol";
  return {};
}

BandSkies make_band_skies(const SkySpec& spec, std::span<const std::string> bands, const SiteAtmosphere& site,
                          const std::filesystem::path& cache_dir, int threads) {
  BandSkies out;
  if (spec.model != "vrte") {
    out.skies.push_back(make_sky(spec));  // grey: one model for every band, exactly as before
    return out;
  }
  validate(spec);
  if (bands.empty()) bad("model", "vrte needs at least one band");
  const std::vector<double> wavelengths = band_wavelengths_nm(spec, bands);
  vrte::TableOptions options;
  options.streams = spec.streams;
  options.grid = spec.grid;
  options.threads = threads;
  for (std::size_t i = 0; i < wavelengths.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const LayerOptics optics =
        layer_optics(wavelengths[i], site.pressure_hpa, site.altitude_m, site.latitude_deg, spec.aerosol);
    std::shared_ptr<const vrte::VrteTable> table;
    if (cache_dir.empty()) {
      table = std::make_shared<const vrte::VrteTable>(vrte::VrteTable::build(optics, spec.ground_albedo, options));
      ++out.tables_built;
    } else {
      bool hit = false;
      table = std::make_shared<const vrte::VrteTable>(
          vrte::VrteTable::cached(optics, spec.ground_albedo, options, cache_dir, &hit));
      ++(hit ? out.tables_read : out.tables_built);
    }
    out.build_seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    out.skies.push_back(wrap(std::make_unique<VrteSky>(std::move(table)), spec));
  }
  return out;
}

std::unique_ptr<SkyModel> make_sky(const SkySpec& spec) {
  validate(spec);
  if (spec.model == "vrte") bad("model", "vrte is one model per band: build it with make_band_skies");
  const double pmax = effective_max_dolp(spec);
  std::unique_ptr<SkyModel> sky;
  if (spec.model == "berry") {
    sky = std::make_unique<BerrySky>(
        BerryParams{pmax, spec.separation_deg, parse_berry_normalisation(spec.berry_normalisation)});
  } else {
    sky = std::make_unique<RayleighSky>(RayleighParams{pmax});
  }
  // Both patterns carry the Rayleigh phase radiance already; wrap only to change it.
  IntensityParams radiance;
  radiance.model = intensity_model_from_name(spec.intensity);
  radiance.turbidity = spec.turbidity;
  if (radiance.model != IntensityModel::rayleigh) sky = std::make_unique<IntensitySky>(std::move(sky), radiance);
  return wrap(std::move(sky), spec);
}

}  // namespace skypol::sky
