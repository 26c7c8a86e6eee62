// The [sky] section (and [sky.clouds]): which polarization pattern and radiance, checked here
// key by key and then by sky::validate for the combinations (Preetham's turbidity range).
#include <limits>

#include "scene/scene.h"

namespace skypol::scene {

sky::SkySpec read_sky(Fields& f) {
  sky::SkySpec s;
  s.model = f.choice("model", s.model, {"rayleigh", "berry"});
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

}  // namespace skypol::scene
