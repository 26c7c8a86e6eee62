// How much of the sky does not look like a clear sky: the cloud/model-mismatch measure behind the
// cloud gate of run_method (evaluate.h), read from the stack's own DoLP.
//
// Cloud mixes unpolarized light into the clear sky (sky/clouds.h): under a cloud of opacity
// α > ½ the DoLP falls below ≈ 0.3 of the clear sky's. A clear single-scattering sky is that
// weakly polarized only near its neutral points, within ≈ 35° of the sun and the antisun
// (Rayleigh: sin²γ/(1+cos²γ) < 0.2 for γ < 35°; Berry's neutral points lie within ≈ 25° of them).
// So per frame: leave out the pixels within 40° of the sun and of the antisun (find_suns; a frame
// without a sun-like minimum keeps all its pixels), and count the share of the rest whose DoLP is
// below 20 % of the frame's 99th percentile. The stack's share is the mean over its frames.
// A clear sky scores ≈ 0; a sky half under thick cloud ≈ ½.
#pragma once

#include "skypole/sky_images.h"

namespace skypol::skypole {

double unpolarized_share(const SkyImages& sky);

}  // namespace skypol::skypole
