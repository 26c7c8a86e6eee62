// The vrte entry of the sky models' registry: multiple scattering by molecules and one aerosol,
// one model per band, each over its own table (sky/vrte/vrte_sky.h, vrte_table.h) read from or
// written to the cache.
#include <chrono>

#include "sky/vrte/aerosol_types.h"
#include "sky/vrte/optical_depth.h"
#include "sky/spec_errors.h"
#include "sky/sky_model_registry.h"
#include "sky/vrte/vrte_sky.h"
#include "sky/vrte/vrte_table.h"

namespace skypol::sky {
namespace {

SkyKey aerosol_key() {
  std::vector<std::string> types = aerosol_type_names();
  types.insert(types.end(), {"custom", "none"});
  auto custom_only = [](const SkySpec& s) {
    return s.aerosol.type == "custom" ? std::string() : std::string("used only by type \"custom\" (a named type has its own)");
  };
  std::vector<SkyKey> keys{
      choice_key("type", types, [](SkySpec& s) -> std::string& { return s.aerosol.type; }),
      number_key("median_radius_um", 1e-4, 20, [](SkySpec& s) -> double& { return s.aerosol.median_radius_um; }),
      number_key("geometric_std", 1.000001, 3, [](SkySpec& s) -> double& { return s.aerosol.geometric_std; }),
      number_key("refractive_real", 1, 3, [](SkySpec& s) -> double& { return s.aerosol.refractive_real; }),
      number_key("refractive_imag", 0, 2, [](SkySpec& s) -> double& { return s.aerosol.refractive_imag; }),
      number_key("tau_550", 0, 10, [](SkySpec& s) -> double& { return s.aerosol.tau_550; }),
      optional_number_key("angstrom", -1, 4, [](SkySpec& s) -> std::optional<double>& { return s.aerosol.angstrom; }),
      optional_number_key("ssa", 0, 1, [](SkySpec& s) -> std::optional<double>& { return s.aerosol.ssa; }),
      integer_key("angle_nodes", 16, 4096, [](SkySpec& s) -> int& { return s.aerosol.angle_nodes; })};
  for (std::size_t i = 1; i <= 4; ++i) keys[i].refuse = custom_only;
  SkyKey t = table_key("aerosol", std::move(keys));
  t.check = [](const SkySpec& s) { validate(s.aerosol); };  // "sky.aerosol.<field>: …"
  return t;
}

BandSkies make_vrte_bands(const SkySpec& spec, std::span<const std::string> bands, const SiteAtmosphere& site,
                          const std::filesystem::path& cache_dir, int threads) {
  if (bands.empty()) spec_error("sky.model", "vrte needs at least one band");
  BandSkies out;
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
    out.build_seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    out.skies.push_back(std::make_unique<VrteSky>(std::move(table)));
  }
  return out;
}

}  // namespace

SkyModelEntry vrte_sky_model() {
  SkyModelEntry e;
  e.name = "vrte";
  e.description = "multiple scattering by molecules and aerosol over a Lambertian ground, solved per band";
  e.keys = {number_key("ground_albedo", 0, 1, [](SkySpec& s) -> double& { return s.ground_albedo; }),
            integer_key("streams", 4, 64, [](SkySpec& s) -> int& { return s.streams; }),
            integer_key("grid", 8, 129, [](SkySpec& s) -> int& { return s.grid; }),
            numbers_key("wavelengths_nm", 200, 4000, [](SkySpec& s) -> std::vector<double>& { return s.wavelengths_nm; }),
            aerosol_key()};
  e.keys[3].range_note = "nm, Bodhaine's formula";
  e.make_bands = make_vrte_bands;
  e.check_scene = [](const SkySpec& s, std::span<const std::string> bands, const SiteAtmosphere& site) {
    // Every band needs a wavelength, and Bodhaine's Rayleigh depth a site it is defined for.
    (void)band_wavelengths_nm(s, bands);
    if (site.altitude_m < -500 || site.altitude_m > 10000) {
      spec_error("sky.model", "vrte: the site's height_m must be in [-500, 10000] m (Bodhaine's Rayleigh depth)");
    }
  };
  return e;
}

}  // namespace skypol::sky
