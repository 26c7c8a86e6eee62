// The registry entry (method_registry.h) of sun_azimuth (sun_azimuth.h).
#include "skypole/method_registry.h"
#include "skypole/sun_azimuth.h"

namespace skypol::skypole {

Method sun_azimuth_method() {
  Method m;
  m.name = "sun_azimuth";
  m.description =
      "the suns' azimuths (unbiased by multiple scattering) and the clock: latitude and north by a celestial fix "
      "(sun_azimuth.h)";
  m.bare = [](const SkyView& view) {
    SunAzimuthParams p;
    p.input = view.input();
    return estimate_sun_azimuth(view, p);
  };
  m.traits = {.frame_jackknife_max_groups = 6, .sector_jackknife = true};
  // Both jackknives, shrunk: the raw pair over-covers on the realistic population, the frame
  // jackknife alone misses what an unequal sky on the two sides of the sun's vertical shares by
  // every frame. The floor is the fix's own model accuracy. No Rayleigh-law gate: the azimuths do
  // not depend on the law.
  m.calibration = {.method = m.name, .inflation = 0.7, .floor_deg = 0.002, .max_residual_deg = 5.0,
                   .sector_inflation = 0.35};
  return m;
}

}  // namespace skypol::skypole
