// Building a sky model from plain values, so that the scene loader needs to know no model class.
// Only what a spec asks for is built: the default spec gives a bare RayleighSky. Wrappers, inner
// to outer: IntensitySky (radiance ≠ rayleigh), CloudySky (coverage > 0), SunDiscSky (sun_disc).
#pragma once

#include <memory>
#include <string>

#include "sky/clouds.h"
#include "sky/sky_model.h"

namespace skypol::sky {

// Field names are the TOML keys of a scene's [sky] table (docs/scenes.md); errors use them.
struct SkySpec {
  std::string model = "rayleigh";         // polarization pattern: "rayleigh" | "berry"
  double max_dolp = 1.0;                  // Pmax ∈ [0, 1]
  bool max_dolp_from_turbidity = false;   // true: Pmax = exp(−(T − 0.6)/4) (depolarization.h)
  double separation_deg = 20.0;           // berry: neutral points' distance from the sun, [0, 45]
  std::string berry_normalisation = "split_rayleigh";  // berry: |w| → DoLP, "split_rayleigh" | "opensky" (berry.h)
  std::string intensity = "rayleigh";     // radiance: "uniform" | "rayleigh" | "preetham"
  double turbidity = 3.0;                 // ≥ 1; preetham needs [2, 10]
  bool sun_disc = false;                  // add the sun's disc (radius 0.2666°)
  double sun_disc_radiance = 2.0e5;       // ≥ 0, relative units (≈ solar/zenith-sky luminance)
  CloudParams clouds;                     // clouds.coverage = 0: clear sky, nothing built
};

// Throws std::invalid_argument whose message starts with the field ("sky.intensity: …"),
// states the value and lists the legal values or range. make_sky calls it first.
void validate(const SkySpec& spec);

std::unique_ptr<SkyModel> make_sky(const SkySpec& spec);

// The Pmax a spec yields (max_dolp, or the turbidity form when asked).
double effective_max_dolp(const SkySpec& spec);

}  // namespace skypol::sky
