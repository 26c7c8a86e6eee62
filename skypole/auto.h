// auto: one answer from the methods' answers on a stack. The answers that agree within their
// uncertainty form a group; auto returns the answer of a method that answers alone in it, or else
// their inverse-variance mean with the σ of the sharpest, and declines when the data do not decide.
// The rule itself is auto_choice (uncertainty.h); run_method(stack, "auto") (evaluate.h) runs the
// methods first.
#pragma once

#include <string_view>
#include <vector>

#include "stack/frame.h"
#include "skypole/estimate.h"

namespace skypol::skypole {

// auto's combination of answers already computed by run_method (e.g. by `-m all`), without
// running anything again; only the methods used_by_auto(method, site_usable(stack, input)) are
// considered.
PoleEstimate combine_estimates(const stack::Stack& stack, const InputOptions& input,
                               const std::vector<PoleEstimate>& estimates);
// Whether auto weighs `method`'s answer: a registered method whose entry says so and that needs no
// site unless `site_usable`.
bool used_by_auto(std::string_view method, bool site_usable);
// The studies' label for auto's answer with the site withheld (InputOptions::use_site = false:
// site-free, as `--site unknown`), beside "auto", which uses the site where the stack knows it.
inline constexpr const char* kAutoSiteFree = "auto_site_free";

}  // namespace skypol::skypole
