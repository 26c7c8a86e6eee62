// Every estimator on one stack, scored against the stack's truth: the measurement the estimator
// studies (resolution, window, noise) repeat for each setting, and the columns they share.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "studies/tradeoff_table.h"
#include "stack/frame.h"

namespace skypol::studies::tradeoff {

// The columns score_every_method() writes: method, valid, angular_error_deg, bearing_error_deg,
// latitude_error_deg (absolute values, degrees), estimate_s (wall clock), why_invalid.
const std::vector<std::string>& score_columns();

// `first` followed by score_columns(): a study's table header.
std::vector<std::string> with_score_columns(std::vector<std::string> first);

// Each of skypole::method_names() with its defaults (band Y, a perfect level), timed, scored and
// written as a new row of `table`; `setting` fills the caller's columns of each row. An invalid
// estimate, or input the method refuses (std::invalid_argument, e.g. too few frames), leaves the
// error columns empty (valid = 0) and says why.
void score_every_method(const stack::Stack& stack, Table& table,
                        const std::function<void(Table&)>& setting);

}  // namespace skypol::studies::tradeoff
