// The [sky] section (and [sky.clouds], [sky.aerosol]): which polarization pattern and radiance,
// checked here key by key and then by sky::validate for the combinations (Preetham's turbidity
// range). Keys of one model given to another are errors at the key.
#include <limits>
#include <string>
#include <vector>

#include "sky/aerosol_types.h"

#include "scene/scene.h"

namespace skypol::scene {

sky::SkySpec read_sky(Fields& f) {
  sky::SkySpec s;
  s.model = f.choice("model", s.model, {"rayleigh", "berry", "vrte"});
  const bool vrte = s.model == "vrte";
  for (const char* key : {"max_dolp", "max_dolp_from_turbidity", "intensity", "turbidity"}) {
    if (vrte && f.has(key)) f.fail(key, "not used by model \"vrte\" (its radiance and degree come from the solver)");
  }
  for (const char* key : {"ground_albedo", "streams", "grid", "wavelengths_nm", "aerosol"}) {
    if (!vrte && f.has(key)) f.fail(key, "used only by model \"vrte\"");
  }
  s.ground_albedo = f.number("ground_albedo", s.ground_albedo, 0, 1);
  s.streams = static_cast<int>(f.integer("streams", s.streams, 4, 64));
  s.grid = static_cast<int>(f.integer("grid", s.grid, 8, 129));
  s.wavelengths_nm = f.numbers("wavelengths_nm", {});
  for (double w : s.wavelengths_nm) {
    if (!(w >= 200 && w <= 4000)) f.fail("wavelengths_nm", "each wavelength must be in [200, 4000] nm");
  }
  if (std::optional<Fields> a = f.table("aerosol")) {
    sky::AerosolSpec& ae = s.aerosol;
    std::vector<std::string> types = sky::aerosol_type_names();
    types.insert(types.end(), {"custom", "none"});
    ae.type = a->choice("type", ae.type, types);
    const bool custom = ae.type == "custom";
    for (const char* key : {"median_radius_um", "geometric_std", "refractive_real", "refractive_imag"}) {
      if (!custom && a->has(key)) a->fail(key, "used only by type \"custom\" (a named type has its own)");
    }
    ae.median_radius_um = a->number("median_radius_um", ae.median_radius_um, 1e-4, 20);
    ae.geometric_std = a->number("geometric_std", ae.geometric_std, 1.000001, 3);
    ae.refractive_real = a->number("refractive_real", ae.refractive_real, 1, 3);
    ae.refractive_imag = a->number("refractive_imag", ae.refractive_imag, 0, 2);
    ae.tau_550 = a->number("tau_550", ae.tau_550, 0, 10);
    ae.angstrom = a->optional_number("angstrom", -1, 4);
    ae.ssa = a->optional_number("ssa", 0, 1);
    ae.angle_nodes = static_cast<int>(a->integer("angle_nodes", ae.angle_nodes, 16, 4096));
    a->finish();
    try {
      sky::validate(ae);
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      const std::string prefix = "sky.aerosol.";
      std::string key = "type";
      if (m.rfind(prefix, 0) == 0) key = m.substr(prefix.size(), m.find(':') - prefix.size());
      a->fail(key, m.substr(m.find(':') + 2));
    }
  }
  s.max_dolp_from_turbidity = f.boolean("max_dolp_from_turbidity", false);
  if (s.max_dolp_from_turbidity && f.has("max_dolp")) {
    f.fail("max_dolp", "give either 'max_dolp' or 'max_dolp_from_turbidity = true', not both");
  }
  s.max_dolp = f.number("max_dolp", s.max_dolp, 0, 1);
  s.separation_deg = f.number("separation_deg", s.separation_deg, 0, 45);
  if (s.model != "berry" && f.has("separation_deg")) f.fail("separation_deg", "used only by model \"berry\"");
  s.berry_normalisation = f.choice("berry_normalisation", s.berry_normalisation, {"split_rayleigh", "opensky"});
  if (s.model != "berry" && f.has("berry_normalisation")) {
    f.fail("berry_normalisation", "used only by model \"berry\"");
  }
  s.intensity = f.choice("intensity", s.intensity, {"uniform", "rayleigh", "preetham"});
  s.turbidity = f.number("turbidity", s.turbidity, 1, 64);
  if (s.intensity == "preetham" && (s.turbidity < 2 || s.turbidity > 10)) {
    f.fail(f.has("turbidity") ? "turbidity" : "intensity", "Preetham's model is fitted for turbidity in [2, 10]");
  }
  s.sun_disc = f.boolean("sun_disc", false);
  s.sun_disc_radiance = f.number("sun_disc_radiance", s.sun_disc_radiance, 0, 1e12);
  if (std::optional<Fields> c = f.table("clouds")) {
    s.clouds.coverage = c->number("coverage", 0.3, 0, 1);
    s.clouds.seed = static_cast<std::uint64_t>(c->integer("seed", 0, 0, std::numeric_limits<long long>::max()));
    s.clouds.scale_deg = c->number("scale_deg", s.clouds.scale_deg, 1, 90);
    s.clouds.softness = c->number("softness", s.clouds.softness, 1e-6, 1);
    s.clouds.brightness = c->number("brightness", s.clouds.brightness, 1, 1e6);
    c->finish();
  }
  f.finish();
  try {
    sky::validate(s);
  } catch (const std::invalid_argument& e) {
    f.fail("model", e.what());  // every field was range-checked above; this is a safety net
  }
  return s;
}

std::unique_ptr<sky::SkyModel> build_sky(const sky::SkySpec& spec) { return sky::make_sky(spec); }

sky::SiteAtmosphere site_atmosphere(const Scene& scene) {
  sky::SiteAtmosphere a;
  if (scene.sun_options.pressure_hpa > 0) a.pressure_hpa = scene.sun_options.pressure_hpa;  // else 1013.25
  a.altitude_m = scene.site.height_m;
  a.latitude_deg = scene.site.latitude_deg;
  return a;
}

sky::BandSkies build_band_skies(const Scene& scene, const std::filesystem::path& cache_dir) {
  return sky::make_band_skies(scene.sky, scene.render.bands, site_atmosphere(scene), cache_dir);
}

}  // namespace skypol::scene
