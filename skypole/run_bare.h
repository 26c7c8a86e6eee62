// A method by its name, alone: its answer without an uncertainty, gates or calibration — what
// run_method (evaluate.h) answers with before its jackknives, and what they rerun on each view of
// the stack (stack_sky.h: the frames a frame group leaves, the sky without a sector).
#pragma once

#include <string_view>

#include "skypole/estimate.h"
#include "skypole/stack_sky.h"

namespace skypol::skypole {

// The named method (evaluate.h method_names, but "auto") with its defaults and the view's input.
// Throws std::invalid_argument for an unknown name (listing the legal ones) or unusable input.
PoleEstimate run_bare(const SkyView& view, std::string_view method);

}  // namespace skypol::skypole
