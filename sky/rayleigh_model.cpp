// The rayleigh entry of the sky models' registry: single scattering, grey (sky/rayleigh.h).
#include "sky/grey_sky_keys.h"
#include "sky/rayleigh.h"

namespace skypol::sky {

SkyModelEntry rayleigh_sky_model() {
  SkyModelEntry e;
  e.name = "rayleigh";
  e.description = "single scattering in vector form, the same in every band (Pmax scales the degree)";
  e.keys = grey_sky_keys();
  e.validate = validate_grey;
  e.make = [](const SkySpec& s) -> std::unique_ptr<SkyModel> {
    return with_grey_radiance(std::make_unique<RayleighSky>(RayleighParams{effective_max_dolp(s)}), s);
  };
  return e;
}

}  // namespace skypol::sky
