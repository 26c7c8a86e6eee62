// The per-pixel sky mask the fitting methods share (great_circle, invariance, sun_vector,
// sun_dolp; classic never uses it, to stay the paper's algorithm): the pixels a clear
// single-scattering sky cannot explain are left out, rather than the whole sky declined
// (the cloud gate, cloud_share.h).
//
// Per frame, the sun s is fitted robustly (from the AoLP when the stack has it, E ⟂ s; else from a
// Rayleigh fit of the DoLP), then each sky pixel d is judged against that frame's clear sky:
//  - low DoLP: where the Rayleigh shape g = (1 − c²)/(1 + c²), c = s·d, is at least `min_shape`
//    (≈ 43° or more from the sun and antisun, away from the neutral points), DoLP/g below
//    `low_ratio` of the frame's 90th percentile of DoLP/g. A cloud of opacity α scales DoLP by
//    1 − α (sky/clouds.h), so α > ½ is caught whatever the sky's Pmax;
//  - wrong AoLP: E more than max(`aolp_min_deg`, 4 robust σ) out of the plane ⟂ s (DoLP ≥ 0.05);
//  - saturated (S0 ≥ `saturated` × the frame's largest S0) or dark (S0 ≤ `dark` × its median),
//    when the stack has "S0.<band>": the DoLP and AoLP of clipped or noise-floor pixels are wrong.
// A pixel is masked when it was bad in at least `bad_share` of the frames that could judge it:
// clouds stand still while the sky's pattern turns with the sun, so a pixel that is bad in a
// quarter of its frames is inconsistent over time, and every method here fits all frames at once.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "camera/camera.h"
#include "stack/frame.h"
#include "skypole/sky_images.h"

namespace skypol::skypole {

struct SkyMaskParams {
  double min_shape = 0.3;
  double low_ratio = 0.5;
  double aolp_min_deg = 10.0;
  double saturated = 0.98;
  double dark = 0.05;
  double bad_share = 0.25;
};

struct SkyMask {
  std::vector<std::uint8_t> masked;  // 1 = left out (only ever a valid sky pixel)
  int masked_count = 0;
  int low_dolp = 0, wrong_aolp = 0, saturated = 0, dark = 0;  // pixels bad at least once, per cause
  std::vector<std::optional<Eigen::Vector3d>> suns;            // per frame, the suns it judged by
};

// The unit E-vector (camera frame) of a pixel looking along unit d_cam whose sensor AoLP is
// `aolp` (radians), through the camera's transport; nullopt where it is undefined (projected
// transport with d ⟂ the optical axis).
std::optional<Eigen::Vector3d> e_vector(const Eigen::Vector3d& d_cam, double aolp, camera::Transport t);

SkyMask compute_sky_mask(const SkyImages& sky, const stack::Stack& stack, const SkyMaskParams& p = {});

// compute_sky_mask, then clears the masked pixels' `valid` (and recounts valid_count), unless that
// would leave fewer than 50 pixels. Returns the mask.
SkyMask apply_sky_mask(SkyImages& sky, const stack::Stack& stack, const SkyMaskParams& p = {});

}  // namespace skypol::skypole
