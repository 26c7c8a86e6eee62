// What the grey models (rayleigh, berry: one pattern for every band) share: the keys of their
// degree and radiance (max_dolp, max_dolp_from_turbidity, intensity, turbidity), the checks over
// them, and the radiance wrapper they ask for.
#pragma once

#include <memory>
#include <vector>

#include "sky/sky_model_registry.h"

namespace skypol::sky {

std::vector<SkyKey> grey_sky_keys();

// Turbidity ≥ 1 and Preetham's [2, 10]; throws std::invalid_argument("sky.turbidity: …").
void validate_grey(const SkySpec& spec);

// `pattern` under the radiance the spec asks for (IntensitySky unless it is Rayleigh's, which both
// patterns carry already).
std::unique_ptr<SkyModel> with_grey_radiance(std::unique_ptr<SkyModel> pattern, const SkySpec& spec);

}  // namespace skypol::sky
