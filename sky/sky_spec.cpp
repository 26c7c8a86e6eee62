#include "sky/sky_spec.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "sky/clouds.h"
#include "sky/vrte/optical_depth.h"
#include "sky/sky_model_registry.h"
#include "sky/spec_errors.h"
#include "sky/sun_disc.h"

namespace skypol::sky {
namespace {

// The field names below are relative to "sky" (sky/spec_errors.h words the message).
[[noreturn]] void bad(const std::string& field, const std::string& message) { spec_error("sky." + field, message); }

std::string choices_text(const std::vector<std::string>& legal) {
  std::string out;
  for (std::size_t i = 0; i < legal.size(); ++i) out += (i == 0 ? "" : i + 1 == legal.size() ? " or " : ", ") + legal[i];
  return out;
}

void check_range(const std::string& field, double v, const SkyKey& k) {
  if (!(v >= k.lo && v <= k.hi)) {
    spec_error(field, spec_number(v) + " is outside [" + spec_number(k.lo) + ", " + spec_number(k.hi) + "]" +
                   (k.range_note.empty() ? "" : " (" + k.range_note + ")"));
  }
}

// Each key's value in its range or among its legal values, sub-tables' keys and checks included.
void check_keys(const std::vector<SkyKey>& keys, const std::string& prefix, const SkySpec& s) {
  for (const SkyKey& k : keys) {
    const std::string field = prefix + k.name;
    if (k.kind == SkyKey::Kind::table) {
      check_keys(k.keys, field + ".", s);
      if (k.check) k.check(s);
      continue;
    }
    if (k.refuse && !k.refuse(s).empty()) continue;  // not in use with the rest of the spec
    if (k.scene_range_only) continue;
    const SkyValue v = k.get(s);
    if (const double* d = std::get_if<double>(&v)) check_range(field, *d, k);
    if (const long long* i = std::get_if<long long>(&v)) check_range(field, static_cast<double>(*i), k);
    if (const auto* a = std::get_if<std::vector<double>>(&v))
      for (double x : *a) check_range(field, x, k);
    if (const std::string* c = std::get_if<std::string>(&v); c && k.kind == SkyKey::Kind::choice) {
      if (std::find(k.legal.begin(), k.legal.end(), *c) == k.legal.end())
        spec_error(field, "\"" + *c + "\" is unknown (expected " + choices_text(k.legal) + ")");
    }
  }
}

// The wrappers every model takes: clouds, then the sun's disc over them.
std::unique_ptr<SkyModel> wrap(std::unique_ptr<SkyModel> sky, const SkySpec& spec) {
  if (spec.clouds.coverage > 0.0) sky = std::make_unique<CloudySky>(std::move(sky), spec.clouds);
  if (spec.sun_disc) sky = std::make_unique<SunDiscSky>(std::move(sky), spec.sun_disc_radiance);
  return sky;
}

}  // namespace

void validate(const SkySpec& s) {
  const SkyModelEntry& m = sky_model_entry(s.model);  // "sky.model: … is unknown"
  if (m.validate) m.validate(s);
  check_keys(m.keys, "sky.", s);
  check_keys(every_model_keys(), "sky.", s);
}

void validate_for_scene(const SkySpec& spec, std::span<const std::string> bands, const SiteAtmosphere& site) {
  const SkyModelEntry& m = sky_model_entry(spec.model);
  if (m.check_scene) m.check_scene(spec, bands, site);
}

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
  const SkyModelEntry& m = sky_model_entry(spec.model);
  BandSkies out;
  if (!m.make_bands) {
    out.skies.push_back(make_sky(spec));  // one model for every band
    return out;
  }
  validate(spec);
  out = m.make_bands(spec, bands, site, cache_dir, threads);
  for (std::unique_ptr<SkyModel>& sky : out.skies) sky = wrap(std::move(sky), spec);
  return out;
}

std::unique_ptr<SkyModel> make_sky(const SkySpec& spec) {
  validate(spec);
  const SkyModelEntry& m = sky_model_entry(spec.model);
  if (!m.make) bad("model", spec.model + " is one model per band: build it with make_band_skies");
  return wrap(m.make(spec), spec);
}

}  // namespace skypol::sky
