// What the tests of the sector jackknife read off an uncalibrated answer: its error against the
// stack's truth and each jackknife's σ on its own (degrees).
#pragma once

#include <iostream>
#include <string>

#include <catch2/catch.hpp>

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

// `method` run uncalibrated on a clear stack and on the same stack veiled, both required valid,
// with their readings, printed under `label`: what each sector-jackknife test compares.
struct ClearAndVeiled {
  skypole::PoleEstimate clear, veiled;
  JackknifeReading c, v;
};

inline ClearAndVeiled read_clear_and_veiled(const std::string& method, const stack::Stack& clear,
                                            const stack::Stack& veiled, const skypole::InputOptions& input) {
  ClearAndVeiled r{skypole::run_method(clear, method, input), skypole::run_method(veiled, method, input), {}, {}};
  INFO(r.clear.why_invalid << " / " << r.veiled.why_invalid);
  REQUIRE(r.clear.valid);
  REQUIRE(r.veiled.valid);
  r.c = jackknife_reading(r.clear, clear);
  r.v = jackknife_reading(r.veiled, veiled);
  std::cout << method << " sector jackknife: clear error " << r.c.error_deg << "°, σ frames " << r.c.frames_deg
            << "°, σ sectors " << r.c.sectors_deg << "°; veiled error " << r.v.error_deg << "°, σ frames "
            << r.v.frames_deg << "°, σ sectors " << r.v.sectors_deg << "°\n";
  return r;
}

}  // namespace skypol::testing
