// What the tests of the sector jackknife read off an uncalibrated answer: its error against the
// stack's truth and each jackknife's σ on its own (degrees).
#pragma once

#include "skypole/evaluate.h"
#include "skypole/uncertainty.h"
#include "stack/frame.h"

namespace skypol::testing {

struct JackknifeReading {
  double error_deg = 0, frames_deg = 0, sectors_deg = 0;
};

inline JackknifeReading jackknife_reading(const skypole::PoleEstimate& e, const stack::Stack& stack) {
  return {skypole::score(e, stack.frames.front().truth).angular_error_deg,
          skypole::sigma_deg_of(e.jackknife_frames_rad2), skypole::sigma_deg_of(e.jackknife_sectors_rad2)};
}

}  // namespace skypol::testing
