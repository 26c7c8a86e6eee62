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
//  4. sub-pixel, by one of two local models around the winner (invariance_refine.h):
//     corotating (default when the frames' times differ): the sky's pattern is fixed to the sun,
//       which turns about the pole; so in the frame turning with it about the true pole EVERY
//       direction's DoLP is invariant, not only the pole's. For a candidate pole P, each pixel's
//       direction in frame t is turned back about P by the sun's hour-angle change since the
//       middle instant (and along its hour circle by its declination change, both from the
//       frames' times through ERFA, which need no site), and all frames' DoLP within
//       corotating_radius_deg of P are fitted by ONE quartic of the turned tangent-plane
//       coordinates; P minimises the variance left. One shared pattern averages the noise over
//       every pixel and frame of a wide window, which the flat equinox minimum needs (V ∝ |u|⁴
//       there: a few pixels of noisy DoLP cannot place it).
//     per_frame (the only choice when all frames carry one time): each frame's DoLP within
//       fit_radius_px fitted by its own cubic in gnomonic tangent-plane coordinates, and V of
//       these polynomials minimised by Levenberg–Marquardt, re-centred if the minimum leaves the
//       window. Exact on noise-free stacks; sensor noise moves it by degrees near the equinox.
// Invalid when the fit window does not fit inside the usable image (the co-rotating window first
// shrinks, down to corotating_min_radius_deg); the reason names what is nearest, masked sky or the
// edge of the field of view, and both causes: the pole beyond it, or a minimum a short or noisy
// window left shallow. residual_deg: 1-σ angular uncertainty from the curvature of V and
// the residual scatter at the minimum. Uncertainty: skypole/uncertainty.h.
#pragma once

#include <optional>

#include "stack/frame.h"
#include "skypole/estimate.h"
#include "skypole/sky_images.h"
#include "skypole/stack_sky.h"

namespace skypol::skypole {

enum class Detrend { none, linear, automatic };
enum class Refine { per_frame, corotating, automatic };
Detrend parse_detrend(std::string_view name);  // "none" | "linear" | "automatic"
std::string_view detrend_name(Detrend d);
Refine parse_refine(std::string_view name);  // "per_frame" | "corotating" | "automatic"
std::string_view refine_name(Refine r);

struct InvarianceParams {
  InputOptions input;
  std::optional<double> filter_radius_px;  // nullopt → default_filter_radius_px
  double coarse_step_deg = 2.0;
  int candidates = 3;
  // Step 4: automatic = corotating when the frames were taken at different times, else per_frame.
  Refine refine = Refine::automatic;
  // per_frame: radius and degree of each frame's polynomial; nullopt → max(3, 1 % of the shorter
  // side) pixels.
  std::optional<double> fit_radius_px;
  int per_frame_degree = 3;
  // corotating: the window's radius on the sky (shrunk to what the usable image holds around the
  // minimum, down to the minimum radius) and the shared polynomial's degree.
  double corotating_radius_deg = 15;
  double corotating_min_radius_deg = 4;
  int corotating_degree = 4;
  // Turn the sun's declination drift (from the frames' times, oriented by the suns the images show)
  // into the co-rotating model; off: a rigid turn about the pole.
  bool model_declination_drift = true;
  // automatic: linear when the frames span ≥ auto_detrend_min_hours and there are ≥ 5 frames
  // (over a short window every direction's DoLP is nearly linear in time: detrending would erase
  // the signal).
  Detrend detrend = Detrend::automatic;
  double auto_detrend_min_hours = 4.0;
  // The sector jackknife (uncertainty.h), done inside the co-rotating fit: its window's samples are
  // dealt into this many azimuth sectors about the minimum and the minimum refitted without each
  // (InvarianceResult::without_sector). 0: none. A wedge of the whole sky masked instead would
  // cut into the window about the pole and trip its edge checks.
  int sectors = 0;
};

struct InvarianceResult {
  PoleEstimate estimate;
  // With params.sectors > 0 and the co-rotating fit: the answer without each sector of its window
  // (invalid, with the reason, where the refit found no minimum). Empty otherwise.
  std::vector<PoleEstimate> without_sector;
  double dolp_rms_at_pole = 0;  // √V at the minimum (DoLP units)
  bool detrended = false;
  bool corotating = false;  // which step 4 ran
  double window_deg = 0;    // radius of step 4's window on the sky
  // corotating: the sense the sky's pattern turns in about the minimum found (−1 clockwise by the
  // right-hand rule about it: it is the NCP; +1: the SCP) and how much worse the other sense fits
  // (≥ 1). Used for north/south when the suns in view cannot tell (contrast ≥ 2).
  int rotation_sense = 0;
  double rotation_sense_contrast = 0;
};

// Which end of the axis is the NCP, from two witnesses of the sky's rotation: `suns`, the suns'
// turn (decide_hemisphere, with the user's hint), and the co-rotating fit's sense (pattern_sense:
// −1 NCP, +1 SCP, 0 none; it speaks when the other sense fits at least min_contrast times worse).
// The suns here are the lowest DoLP above the horizon, which a sky with neutral points apart from
// the sun (Berry's, a multiply scattering one) can place on a neutral point, so that they name the
// wrong end (docs/calibration-history.md, "Measurements behind the code's constants"); the pattern
// is the whole sky.
//  - the suns cannot tell: the pattern decides;
//  - the suns decided without a hint and the pattern says the other end: declined (!ok, `why`);
//  - the suns overrode the user's hint and the pattern sides with the hint: the hint stands, and
//    `source` says why;
//  - otherwise `suns` stands.
HemisphereDecision reconcile_hemisphere(HemisphereDecision suns, int pattern_sense, double pattern_contrast,
                                        double min_contrast, Hemisphere hint);

// Needs at least 3 frames. Throws std::invalid_argument for unusable input (estimate.h).
InvarianceResult estimate_invariance(const stack::Stack& stack, const InvarianceParams& params = {});
// The same on a view of a stack (stack_sky.h: a jackknife's sub-run); params.input is the view's.
InvarianceResult estimate_invariance(const SkyView& view, const InvarianceParams& params = {});

}  // namespace skypol::skypole
