#include "sky/sky_spec.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sky/berry.h"
#include "sky/depolarization.h"
#include "sky/intensity.h"
#include "sky/rayleigh.h"
#include "sky/sun_disc.h"

namespace skypol::sky {
namespace {

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

[[noreturn]] void bad(const std::string& field, const std::string& message) {
  throw std::invalid_argument("sky." + field + ": " + message);
}

void check_range(const std::string& field, double v, double lo, double hi, const std::string& why = "") {
  if (!(v >= lo && v <= hi)) {
    bad(field, num(v) + " is outside [" + num(lo) + ", " + num(hi) + "]" + (why.empty() ? "" : " (" + why + ")"));
  }
}

}  // namespace

void validate(const SkySpec& s) {
  if (s.model != "rayleigh" && s.model != "berry") {
    bad("model", "\"" + s.model + "\" is unknown (expected rayleigh or berry)");
  }
  if (s.intensity != "uniform" && s.intensity != "rayleigh" && s.intensity != "preetham") {
    bad("intensity", "\"" + s.intensity + "\" is unknown (expected uniform, rayleigh or preetham)");
  }
  if (!(std::isfinite(s.turbidity) && s.turbidity >= 1.0)) {
    bad("turbidity", num(s.turbidity) + " must be ≥ 1 (1 = a pure molecular atmosphere)");
  }
  if (s.intensity == "preetham") check_range("turbidity", s.turbidity, 2.0, 10.0, "Preetham's fit");
  if (!s.max_dolp_from_turbidity) check_range("max_dolp", s.max_dolp, 0.0, 1.0);
  check_range("separation_deg", s.separation_deg, 0.0, 45.0);
  if (s.berry_normalisation != "split_rayleigh" && s.berry_normalisation != "opensky") {
    bad("berry_normalisation",
        "\"" + s.berry_normalisation + "\" is unknown (expected split_rayleigh or opensky)");
  }
  if (!(std::isfinite(s.sun_disc_radiance) && s.sun_disc_radiance >= 0.0)) {
    bad("sun_disc_radiance", num(s.sun_disc_radiance) + " must be ≥ 0");
  }
  check_range("clouds.coverage", s.clouds.coverage, 0.0, 1.0);
  check_range("clouds.scale_deg", s.clouds.scale_deg, 1.0, 90.0);
  if (!(s.clouds.softness > 0.0 && s.clouds.softness <= 1.0)) {
    bad("clouds.softness", num(s.clouds.softness) + " is outside (0, 1]");
  }
  if (!(std::isfinite(s.clouds.brightness) && s.clouds.brightness >= 1.0)) {
    bad("clouds.brightness", num(s.clouds.brightness) + " must be ≥ 1 (cloud is brighter than the sky behind it)");
  }
}

double effective_max_dolp(const SkySpec& spec) {
  return spec.max_dolp_from_turbidity ? max_dolp_from_turbidity(spec.turbidity) : spec.max_dolp;
}

std::unique_ptr<SkyModel> make_sky(const SkySpec& spec) {
  validate(spec);
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
  if (spec.clouds.coverage > 0.0) sky = std::make_unique<CloudySky>(std::move(sky), spec.clouds);
  if (spec.sun_disc) sky = std::make_unique<SunDiscSky>(std::move(sky), spec.sun_disc_radiance);  // over clouds
  return sky;
}

}  // namespace skypol::sky
