// The tables `skypol evaluate` writes: one CSV row per (stack, method), the per-method summary as
// CSV, and the summary as a fixed-width table for a terminal. CSV: RFC 4180 quoting, '.'
// decimals, an undefined value (bearing at a geographic pole, any error of an invalid row) is an
// empty field — never NaN.
#pragma once

#include <string>
#include <vector>

#include "skypole/evaluate_summary.h"

namespace skypol::skypole {

// Columns: dataset,method,valid,why_invalid,heading_deg,latitude_deg,azimuth_rel_deg,altitude_deg,
// is_north,true_heading_deg,true_latitude_deg,bearing_error_deg,latitude_error_deg,
// angular_error_deg,residual_deg,sigma_bearing_deg,sigma_latitude_deg,cone95_deg,sigma_deg,
// seconds,note
std::string rows_csv(const std::vector<EvaluationRow>& rows);
// Columns: method,rows,valid,{bearing,latitude,angular}_{n,mean,median,p95,max},mean_seconds
std::string summary_csv(const std::vector<MethodSummary>& summaries);
// One CSV field, quoted as RFC 4180 asks when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& s);
// A fixed-width table for a terminal.
std::string summary_text(const std::vector<MethodSummary>& summaries);

}  // namespace skypol::skypole
