// The berry entry of the sky models' registry: Berry, Dennis & Lee's four neutral points, grey
// (sky/berry.h). It takes the grey models' keys and its own separation and normalisation.
#include "sky/berry.h"
#include "sky/grey_sky_keys.h"

namespace skypol::sky {

SkyModelEntry berry_sky_model() {
  SkyModelEntry e;
  e.name = "berry";
  e.description = "Berry-Dennis-Lee sky: neutral points at separation_deg from the sun and anti-sun, grey";
  e.keys = grey_sky_keys();
  e.keys.push_back(number_key("separation_deg", 0, 45, [](SkySpec& s) -> double& { return s.separation_deg; }));
  e.keys.push_back(choice_key("berry_normalisation", {"split_rayleigh", "opensky"},
                              [](SkySpec& s) -> std::string& { return s.berry_normalisation; }));
  e.validate = validate_grey;
  e.make = [](const SkySpec& s) -> std::unique_ptr<SkyModel> {
    return with_grey_radiance(
        std::make_unique<BerrySky>(BerryParams{effective_max_dolp(s), s.separation_deg,
                                               parse_berry_normalisation(s.berry_normalisation)}),
        s);
  };
  return e;
}

}  // namespace skypol::sky
