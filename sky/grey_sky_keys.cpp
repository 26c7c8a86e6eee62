#include "sky/grey_sky_keys.h"

#include <cmath>

#include "sky/depolarization.h"
#include "sky/intensity.h"
#include "sky/spec_errors.h"

namespace skypol::sky {

std::vector<SkyKey> grey_sky_keys() {
  SkyKey max_dolp = number_key("max_dolp", 0, 1, [](SkySpec& s) -> double& { return s.max_dolp; });
  max_dolp.refuse = [](const SkySpec& s) {
    return s.max_dolp_from_turbidity ? std::string("give either 'max_dolp' or 'max_dolp_from_turbidity = true', not both")
                                     : std::string();
  };
  return {max_dolp,
          boolean_key("max_dolp_from_turbidity", [](SkySpec& s) -> bool& { return s.max_dolp_from_turbidity; }),
          choice_key("intensity", {"uniform", "rayleigh", "preetham"}, [](SkySpec& s) -> std::string& { return s.intensity; }),
          number_key("turbidity", 1, 64, [](SkySpec& s) -> double& { return s.turbidity; })};
}

void validate_grey(const SkySpec& s) {
  if (!(std::isfinite(s.turbidity) && s.turbidity >= 1.0)) {
    spec_error("sky.turbidity", spec_number(s.turbidity) + " must be ≥ 1 (1 = a pure molecular atmosphere)");
  }
  if (s.intensity == "preetham" && !(s.turbidity >= 2.0 && s.turbidity <= 10.0)) {
    spec_error("sky.turbidity", spec_number(s.turbidity) + " is outside [2, 10] (Preetham's fit)");
  }
}

double effective_max_dolp(const SkySpec& spec) {
  return spec.max_dolp_from_turbidity ? max_dolp_from_turbidity(spec.turbidity) : spec.max_dolp;
}

std::unique_ptr<SkyModel> with_grey_radiance(std::unique_ptr<SkyModel> pattern, const SkySpec& spec) {
  IntensityParams radiance;
  radiance.model = intensity_model_from_name(spec.intensity);
  radiance.turbidity = spec.turbidity;
  if (radiance.model == IntensityModel::rayleigh) return pattern;
  return std::make_unique<IntensitySky>(std::move(pattern), radiance);
}

}  // namespace skypol::sky
