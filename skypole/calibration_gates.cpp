// The calibration's gates (calibration_gates.h).
#include "skypole/calibration_gates.h"

#include <cstdio>
#include <optional>

#include "skypole/cloud_share.h"
#include "skypole/sky_images.h"

namespace skypol::skypole {

// Each gate in turn, the first that declines says why; the sky's images and shares are measured
// only when a gate reads them.
void apply_calibration_gates(PoleEstimate& e, const MethodCalibration& c, const StackSky& whole,
                             std::optional<UnreadableSky>& unread) {
  std::optional<double> ring;
  apply_calibration_gates(e, c, whole, unread, ring);
}

void apply_calibration_gates(PoleEstimate& e, const MethodCalibration& c, const StackSky& whole,
                             std::optional<UnreadableSky>& unread, std::optional<double>& ring) {
  const stack::Stack& stack = whole.stack();
  const InputOptions& input = whole.input();
  if (!e.valid || !input.calibrated) return;
  char buf[640];
  // The readings each gate compares (uncertainty.h gate_declines), filled as the gates need them.
  CalibrationReadings r;
  r.residual_deg = e.residual_deg;
  r.model_misfit = e.model_misfit;
  if (gate_declines(Gate::residual, c, r)) {
    std::snprintf(buf, sizeof buf,
                  "the fit's residual %.2f° is above %.2f°, beyond which this method's error was not predictable "
                  "in the calibration study (cloud, a sky unlike the method's model, or noise)",
                  e.residual_deg, c.max_residual_deg);
    e.valid = false;
    e.why_invalid = buf;
    return;
  }
  if (gate_declines(Gate::model_misfit, c, r)) {
    std::snprintf(buf, sizeof buf,
                  "the sky is not the model this method fits: its DoLP departs from the fitted law by %.1f %% of "
                  "the fitted maximum beyond the images' noise (a multiply scattering sky, haze or cloud), above "
                  "the %.1f %% beyond which this method's error was not predictable in the calibration study",
                  100.0 * e.model_misfit, 100.0 * c.max_model_misfit);
    e.valid = false;
    e.why_invalid = buf;
    return;
  }
  const double window_min =
      (stack.frames.back().truth.time.unix_seconds - stack.frames.front().truth.time.unix_seconds) / 60.0;
  r.window_min = window_min;
  if (gate_declines(Gate::window, c, r)) {
    std::snprintf(buf, sizeof buf,
                  "the window (%.0f min) is shorter than the %.0f min this method needs: the sun's arc is too "
                  "short to fix the pole reliably (calibration study)",
                  window_min, c.min_window_min);
    e.valid = false;
    e.why_invalid = buf;
    return;
  }
  // The sky images the sky-shape gates read, and the shares of it that no method reads, each
  // measured once and only if a gate needs it.
  const auto sky_images = [&]() -> const SkyImages& { return whole.sky(1, e.method); };
  const auto unreadable = [&]() -> const UnreadableSky& {
    if (!unread) unread = unreadable_sky(sky_images());
    return *unread;
  };
  if (input.cloud_gate && gate_set(Gate::unpolarized, c)) {
    const double share = r.unpolarized_share = unreadable().unpolarized;
    if (gate_declines(Gate::unpolarized, c, r)) {
      // Where the sensor clipped part of that sky, the reason says how much, and the cure.
      const double clipped = unreadable().clipped;
      const bool clipping = clipped > 0.005;
      char reading[256];
      if (clipping)
        std::snprintf(reading, sizeof reading,
                      "unpolarized or clipped (clipped by the sensor in some frame, which no method reads: %.0f %%; "
                      "a shorter exposure or a lower gain reads it)",
                      100.0 * clipped);
      else
        std::snprintf(reading, sizeof reading, "%s",
                      "unpolarized (DoLP below 20 % of its 99th percentile; cloud, or the neutral points of a "
                      "multiply scattering sky reaching beyond 40° of the sun and antisun)");
      std::snprintf(buf, sizeof buf,
                    "%s: %.0f %% of the sky away from the sun and antisun is %s, above the %.0f %% beyond which this "
                    "method's error was not predictable in the calibration study",
                    clipping ? "cloud, neutral points or clipping" : "cloud or neutral points", 100.0 * share, reading,
                    100.0 * c.max_unpolarized_share);
      e.valid = false;
      e.why_invalid = buf;
      return;
    }
  }
  if (gate_set(Gate::clipped, c)) {
    const double clipped = r.clipped_share = unreadable().clipped;
    if (gate_declines(Gate::clipped, c, r)) {
      std::snprintf(buf, sizeof buf,
                    "the sensor clipped the sky: %.0f %% of the sky away from the sun and antisun clipped in some "
                    "frame, which no method reads, above the %.0f %% beyond which this method's calibration holds "
                    "no answer; a shorter exposure or a lower gain reads it",
                    100.0 * clipped, 100.0 * c.max_clipped_share);
      e.valid = false;
      e.why_invalid = buf;
      return;
    }
  }
  if (gate_set(Gate::ring_anisotropy, c)) {
    if (!ring) ring = ring_anisotropy(sky_images());
    const double a = r.ring_anisotropy = *ring;
    if (gate_declines(Gate::ring_anisotropy, c, r)) {
      std::snprintf(buf, sizeof buf,
                    "the sky is not the single-scattering shape this method assumes: around the sun its DoLP "
                    "varies by %.0f %% of its range at equal angle from it (neutral points moved by multiple "
                    "scattering), above the %.0f %% beyond which this method's error was not predictable in the "
                    "calibration study",
                    100.0 * a, 100.0 * c.max_ring_anisotropy);
      e.valid = false;
      e.why_invalid = buf;
    }
  }
}

void apply_calibration_gates(PoleEstimate& e, const MethodCalibration& c, const stack::Stack& stack,
                             const InputOptions& input) {
  std::optional<UnreadableSky> unread;
  const StackSky whole(stack, input);
  apply_calibration_gates(e, c, whole, unread);
}

}  // namespace skypol::skypole
