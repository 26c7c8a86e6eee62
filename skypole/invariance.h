// Per-direction time invariance: the pole is the direction of the sky whose DoLP does not change
// over the day (SI eq. 4: s·p = sin δ, constant), found as the minimum over the sphere of the
// variance of DoLP over time.
//
// Why it is better than the classic algorithm: it uses the DoLP values themselves instead of
// thresholded differences (no threshold, no blob), it searches directions on the sphere (so the
// lens only enters through project()), and it ends with a sub-pixel model instead of a pixel.
//
// Steps:
//  1. cost V(d) = mean over frames of r_t², r = H·(DoLP_t(d)), H the projector that removes the
//     mean over frames (and, with Detrend::linear, a linear trend in time: the DoLP at the pole
//     follows the sun's declination drift, ≈ linearly over a day); DoLP_t(d) is the disk-filtered
//     image sampled bilinearly at project(d);
//  2. coarse: V on a Fibonacci lattice of the sky above min_elevation (spacing coarse_step_deg);
//     the best `candidates` separated minima;
//  3. fine: each candidate refined by a shrinking 5×5 pattern search in its tangent plane down to
//     a quarter pixel; the best wins;
//  4. sub-pixel: around the winner each frame's (unfiltered) DoLP is fitted by a quadratic in
//     gnomonic tangent-plane coordinates over the pixels within fit_radius_px, and V of these
//     quadratics is minimised by Levenberg–Marquardt; re-centred if the minimum leaves the window.
// Invalid when the fit window does not fit inside the usable image (pole at the edge of or
// outside the field of view). residual_deg: 1-σ angular uncertainty from the curvature of V and
// the residual scatter at the minimum; confidence: 1 − √(V_min / V_median) over the coarse lattice.
#pragma once

#include <optional>

#include "render/frame.h"
#include "skypole/estimate.h"
#include "skypole/sky_images.h"

namespace skypol::skypole {

enum class Detrend { none, linear, automatic };
Detrend parse_detrend(std::string_view name);  // "none" | "linear" | "automatic"
std::string_view detrend_name(Detrend d);

struct InvarianceParams {
  InputOptions input;
  std::optional<double> filter_radius_px;  // nullopt → default_filter_radius_px
  double coarse_step_deg = 2.0;
  int candidates = 3;
  // Radius of the sub-pixel quadratic fit; nullopt → max(3, 1 % of the shorter side) pixels.
  std::optional<double> fit_radius_px;
  // automatic: linear when the frames span ≥ auto_detrend_min_hours and there are ≥ 5 frames
  // (over a short window every direction's DoLP is nearly linear in time: detrending would erase
  // the signal).
  Detrend detrend = Detrend::automatic;
  double auto_detrend_min_hours = 4.0;
};

struct InvarianceResult {
  PoleEstimate estimate;
  double dolp_rms_at_pole = 0;  // √V at the minimum (DoLP units)
  bool detrended = false;
};

// Needs at least 3 frames. Throws std::invalid_argument for unusable input (estimate.h).
InvarianceResult estimate_invariance(const render::Stack& stack, const InvarianceParams& params = {});

}  // namespace skypol::skypole
