// Building a sky model from plain values, so that the scene loader needs to know no model class.
// Each model is an entry of the registry (sky_model_registry.h) that owns its keys, their checks
// and how it is built; this file holds the values and the calls every caller makes. Only what a
// spec asks for is built: the default spec gives a bare RayleighSky. Wrappers, inner to outer:
// IntensitySky (grey models, radiance ≠ rayleigh), CloudySky (coverage > 0), SunDiscSky (sun_disc).
// The grey models (rayleigh, berry) are one model for every band; the VRTE sky ("vrte") is one
// model per band (make_band_skies), each from its own optical depths and cached table.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "sky/vrte/aerosol_types.h"
#include "sky/clouds.h"
#include "sky/sky_model.h"

namespace skypol::sky {

// One checked value of a [sky] key (sky_model_registry.h, SkyKey); monostate: not given.
using SkyValue = std::variant<std::monostate, bool, long long, double, std::string, std::vector<double>>;

// Field names are the TOML keys of a scene's [sky] table (docs/scenes.md); errors use them. The
// named fields are the shipped models' keys (their entries, rayleigh_model.cpp, berry_model.cpp,
// vrte_model.cpp, say which model takes which); a model added later may keep its keys in params.
struct SkySpec {
  std::string model = "rayleigh";         // a registered model: "rayleigh" | "berry" (grey) | "vrte" (per band)
  double max_dolp = 1.0;                  // Pmax ∈ [0, 1]
  bool max_dolp_from_turbidity = false;   // true: Pmax = exp(−(T − 0.6)/4) (depolarization.h)
  double separation_deg = 20.0;           // berry: neutral points' distance from the sun, [0, 45]
  std::string berry_normalisation = "split_rayleigh";  // berry: |w| → DoLP, "split_rayleigh" | "opensky" (berry.h)
  std::string intensity = "rayleigh";     // radiance: "uniform" | "rayleigh" | "preetham"
  double turbidity = 3.0;                 // ≥ 1; preetham needs [2, 10]
  bool sun_disc = false;                  // add the sun's disc (radius 0.2666°)
  double sun_disc_radiance = 2.0e5;       // ≥ 0, relative units (≈ solar/zenith-sky luminance)
  CloudParams clouds;                     // clouds.coverage = 0: clear sky, nothing built
  // vrte only (max_dolp, intensity and turbidity do not apply: the solver gives radiance and degree).
  AerosolSpec aerosol;                    // [sky.aerosol]; type "none": molecules only
  double ground_albedo = 0.1;             // Lambertian ground under the layer, [0, 1]
  int streams = 12;                       // accuracy: Gauss nodes per hemisphere (vrte/vrte_table.h), [4, 64]
  int grid = 25;                          // table nodes in zenith angle for μ and μ0, [8, 129]
  std::vector<double> wavelengths_nm;     // one per band, nm; empty: band_wavelength_nm(band name)
  // The values of keys that a model declares without a named field above (SkyKey::param), by key.
  std::map<std::string, SkyValue, std::less<>> params;
};

// What the Rayleigh optical depth needs from the site (vrte/optical_depth.h). A scene without a pressure
// (refraction off) uses standard sea-level pressure: the depth needs a real pressure either way.
struct SiteAtmosphere {
  double pressure_hpa = 1013.25;
  double altitude_m = 0.0;
  double latitude_deg = 45.0;
};

// One sky model per band (vrte), or one model for all bands (the grey models: make_sky, exactly
// as before). tables_built / tables_read count the VRTE tables solved and read from the cache;
// build_seconds is the wall time of the solves (0 when every table came from the cache).
struct BandSkies {
  std::vector<std::unique_ptr<SkyModel>> skies;
  int tables_built = 0, tables_read = 0;
  std::vector<double> build_seconds;  // per band, vrte only: time to solve (or read) its table
  // The model of band i (the one model for grey skies).
  const SkyModel& band(std::size_t i) const { return *skies[skies.size() == 1 ? 0 : i]; }
};

// cache_dir: where VRTE tables are read and written (empty: no disk cache, every table solved).
// threads: for the solver (0: all cores). Throws std::invalid_argument naming the field
// ("sky.wavelengths_nm: …", "sky.aerosol.tau_550: …") or the band.
BandSkies make_band_skies(const SkySpec& spec, std::span<const std::string> bands, const SiteAtmosphere& site,
                          const std::filesystem::path& cache_dir, int threads = 0);

// The wavelength (nm) of each band a spec renders: its wavelengths_nm, else band_wavelength_nm.
std::vector<double> band_wavelengths_nm(const SkySpec& spec, std::span<const std::string> bands);

// Where VRTE tables are cached unless told otherwise: $SKYPOL_CACHE_DIR, else
// $XDG_CACHE_HOME/skypol, else $HOME/.cache/skypol, else empty (no cache).
std::filesystem::path default_table_cache_dir();

// Throws std::invalid_argument whose message starts with the field ("sky.intensity: …"),
// states the value and lists the legal values or range: an unknown model, a key of the model (or
// one every model takes) out of its range, then the model's own checks. make_sky calls it first.
void validate(const SkySpec& spec);

// What the scene around a sky must satisfy for its model (vrte: a wavelength for every band, a site
// height Bodhaine's depth is defined for); throws std::invalid_argument("sky.<field>: …").
void validate_for_scene(const SkySpec& spec, std::span<const std::string> bands, const SiteAtmosphere& site);

// Models that are one model for every band (rayleigh, berry): throws for one per band ("vrte"),
// which needs bands (make_band_skies).
std::unique_ptr<SkyModel> make_sky(const SkySpec& spec);

// The Pmax a spec yields (max_dolp, or the turbidity form when asked).
double effective_max_dolp(const SkySpec& spec);

}  // namespace skypol::sky
