// The calibration's gates: where the calibration study found a method's error unpredictable (a
// large residual, a sky unlike the method's model, a short window, an unpolarized, clipped or
// anisotropic sky), the answer is declined with the gate's reason and numbers. The thresholds are
// each method's MethodCalibration (method_registry.h); which gate declines is gate_declines
// (uncertainty.h).
#pragma once

#include <optional>

#include "stack/frame.h"
#include "skypole/cloud_share.h"
#include "skypole/estimate.h"
#include "skypole/stack_sky.h"
#include "skypole/uncertainty.h"

namespace skypol::skypole {

// The gates of `c` on a valid answer `e` of a method on `stack` (run_method applies its own
// method's): declines `e` with the gate's reason and numbers. Nothing when !input.calibrated.
void apply_calibration_gates(PoleEstimate& e, const MethodCalibration& c, const stack::Stack& stack,
                             const InputOptions& input);
// The same on a prepared stack (run_method's): `unread` receives the sky's unpolarized and clipped
// shares when a gate measured them, so that the σ terms do not prepare the same images again.
void apply_calibration_gates(PoleEstimate& e, const MethodCalibration& c, const StackSky& whole,
                             std::optional<UnreadableSky>& unread);
// The same with the sky's ring anisotropy kept in `ring` likewise; a caller that measured the
// shares or the anisotropy already (a stack read frame by frame, classic_stream.h) passes them in
// and the sky is not prepared for them.
void apply_calibration_gates(PoleEstimate& e, const MethodCalibration& c, const StackSky& whole,
                             std::optional<UnreadableSky>& unread, std::optional<double>& ring);

}  // namespace skypol::skypole
