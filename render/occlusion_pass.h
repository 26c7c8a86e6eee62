// The occlusion test over a batch of camera samples, as the renderer's trace_tile runs it: only
// samples that see the sky so far (weight > 0; not outside the image circle) are traced.
#pragma once

#include <span>

#include "render/occluders.h"
#include "sky/sky_model.h"

namespace skypol::render {

// Samples whose ray hits geometry get weight 0. If surface_s0 is non-empty (same size as rays) it
// receives, for those samples, the S0 of the surface hit when the occluders are shaded, and 0
// for every other sample.
void apply_occluders(const Occluders& occluders, std::span<const sky::ViewRay> rays, std::span<float> weight,
                     std::span<float> surface_s0 = {});

}  // namespace skypol::render
