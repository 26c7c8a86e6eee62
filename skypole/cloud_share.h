// How much of the sky does not look like a clear sky: the cloud/model-mismatch measure behind the
// cloud gate of run_method (calibration_gates.h), read from the stack's own DoLP.
//
// Cloud mixes unpolarized light into the clear sky (sky/clouds.h): under a cloud of opacity
// α > ½ the DoLP falls below ≈ 0.3 of the clear sky's. A clear single-scattering sky is that
// weakly polarized only near its neutral points, within ≈ 35° of the sun and the antisun
// (Rayleigh: sin²γ/(1+cos²γ) < 0.2 for γ < 35°; Berry's neutral points lie within ≈ 25° of them).
// So per frame: leave out the pixels within 40° of the sun and of the antisun (find_suns; a frame
// without a sun-like minimum keeps all its pixels), and count the share of the rest whose DoLP is
// below 20 % of the frame's 99th percentile. Sky a sensor masked because it clipped there
// (SkyImages::clipped_rays) counts as such a pixel: a clipped cloud is still a cloud, and clipped
// sky is sky no method reads. The stack's share is the mean over its frames.
// A clear sky scores ≈ 0; a sky half under thick cloud ≈ ½.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "skypole/sky_images.h"

namespace skypol::skypole {

// Both shares from one pass (one find_suns).
struct UnreadableSky {
  double unpolarized = 0;  // the unpolarized share: low DoLP or clipped
  double clipped = 0;      // the part of it that is clipped sky (0 without a sensor's "clipped" channel)
};
UnreadableSky unreadable_sky(const SkyImages& sky);

// How far the sky's DoLP is from a function of the angle to the sun (Rayleigh's and every
// single-scattering sky's shape): per frame, around the lowest DoLP above the horizon (find_suns:
// the sun, or in a real sky a neutral point next to it), the ring 15–35° from it is cut into 8
// sectors; the spread (largest minus smallest sector mean, sectors with ≥ 5 pixels) over the
// frame's 99th percentile. Mean over the frames with ≥ 4 such sectors (0 if none). Rayleigh: the
// noise's (≈ 0); neutral points 15–25° from the sun (Berry's, the multiple-scattering sky's) put
// a second zero on the ring's solar-vertical side, and so a spread of a large part of the range.
double ring_anisotropy(const SkyImages& sky);

// One frame's part of each (frame f of sky, whose sun find_suns found: `sun`), for a stack read one
// frame at a time: unreadable_sky is the sum of the frames' shares over the frame count, and
// ring_anisotropy the mean of the frames' spreads that are not nullopt (0 if none).
UnreadableSky unreadable_share(const SkyImages& sky, std::size_t f, const std::optional<Eigen::Vector3d>& sun);
std::optional<double> ring_spread(const SkyImages& sky, std::size_t f, const std::optional<Eigen::Vector3d>& sun);

}  // namespace skypol::skypole
