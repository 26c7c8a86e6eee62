// What the estimator tests share beyond the synthetic stacks themselves (synthetic_stack.h): the
// paper's day at full size, answers required valid and scored, the checks of a refit from a
// method's cache, the sector-jackknife readings, and hand-made poles for the arithmetic tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "skypole/estimate.h"
#include "stack/frame.h"
#include "synthetic_stack.h"

namespace skypol::testing {

// The paper's day (paper_times) seen by the default 256-pixel camera turned to `heading_deg`, under
// a noise-free Rayleigh sky of Pmax 1: where each method's own tests start.
SyntheticSpec paper_spec(double heading_deg);

// The southern twin of paper_spec: Sydney (33.87° S, 151.21° E) on the same day, local 08:00–16:00
// (UTC+10) every 30 min.
SyntheticSpec sydney_spec(double heading_deg);

// `e` required valid (else the test stops, naming `label` and why), scored against the stack's
// first truth and printed as "<label>: bearing err …°, latitude err …°, angular err …°, residual
// …°<extra>, <seconds> s".
skypole::Score require_scored(const std::string& label, const skypole::PoleEstimate& e,
                              const stack::Stack& stack, const std::string& extra = "");

// keep[i] = 1 for the `frames` frames but those with i % every == at: the frames a refit from a
// method's cache leaves out.
std::vector<std::uint8_t> keep_all_but(std::size_t frames, std::size_t every, std::size_t at);

// What the jackknife relies on (uncertainty.h): a refit from a method's cache with frames left out
// (`cached`) answers as the method re-run on a stack of only the kept frames (`fresh`). Both valid,
// the same hemisphere, poles at most `max_angle_rad` apart, residuals within `residual_margin_deg`.
void check_refit_is_rerun(const skypole::PoleEstimate& cached, const skypole::PoleEstimate& fresh,
                          double max_angle_rad, double residual_margin_deg);

// The input of the sector-jackknife tests: uncalibrated, and without the sky mask (a veil is what
// those tests are about; the mask is tested in sky_mask_test).
skypole::InputOptions uncalibrated_unmasked();

// A VeilPaint (synthetic_stack.h) for `clear`'s frames: DoLP Rayleigh's with Pmax 0.7 for the
// frame's sun turned 10° about East, what a haze or a reflection that follows the sun, but not as
// the sky does, would show; the AoLP is left alone. `clear` must outlive the paint.
VeilPaint rayleigh_of_moved_sun(const stack::Stack& clear);

// What the tests of the sector jackknife read off an uncalibrated answer: its error against the
// stack's truth and each jackknife's σ on its own (degrees).
struct JackknifeReading {
  double error_deg = 0, frames_deg = 0, sectors_deg = 0;
};
JackknifeReading jackknife_reading(const skypole::PoleEstimate& e, const stack::Stack& stack);

// `method` run with `input` on a clear stack and on the same stack veiled, both required valid,
// with their readings, printed: what each sector-jackknife test compares.
struct ClearAndVeiled {
  skypole::PoleEstimate clear, veiled;
  JackknifeReading c, v;
};
ClearAndVeiled read_clear_and_veiled(const std::string& method, const stack::Stack& clear,
                                     const stack::Stack& veiled, const skypole::InputOptions& input);

// The clear noise-free day of a sector test: the answer right and both jackknives small (< 0.05°).
void check_clear_day_small(const ClearAndVeiled& r);
// The veiled day: without the sectors that hold the veil the answer returns, so the sector σ is of
// the error's size (over half of it); the stated σ (uncalibrated: both jackknives and the 0.05°
// floor) holds the error, where the frame jackknife's alone would have been a lie.
void check_sectors_hold_the_veil(const ClearAndVeiled& r);

// A hand-made estimate for the tests that check arithmetic on poles (uncertainty, auto's ranking):
// a valid north pole at a level-frame azimuth and altitude, camera frame = level frame, nothing
// else set.
skypole::PoleEstimate pole_at(double azimuth_deg, double altitude_deg);

}  // namespace skypol::testing
