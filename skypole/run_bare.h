// A method by its name, alone: its answer without an uncertainty, gates or calibration — what
// run_method (evaluate.h) answers with before its jackknives, and what they rerun on each view of
// the stack (stack_sky.h: the frames a frame group leaves, the sky without a sector).
#pragma once

#include <string_view>

#include "skypole/estimate.h"
#include "skypole/method_registry.h"
#include "skypole/stack_sky.h"

namespace skypol::skypole {

// The named method (method_registry.h, but "auto") with its defaults and the view's input: its
// entry's bare run. Throws std::invalid_argument for an unknown name (listing the legal ones), a
// method that needs the site on a stack whose site is unknown or withheld (site_usable), or
// unusable input.
PoleEstimate run_bare(const SkyView& view, std::string_view method);
PoleEstimate run_bare(const SkyView& view, const Method& method);

// Throws std::invalid_argument, saying why, when `method` needs the site and `stack` with `input`
// does not allow it (site_usable).
void check_site(const Method& method, const stack::Stack& stack, const InputOptions& input);

}  // namespace skypol::skypole
