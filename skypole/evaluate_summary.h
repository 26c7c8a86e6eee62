// The statistics of an evaluation: many (estimate, truth) rows scored and summarised per method
// (mean, median, p95, max of |error|). Over the valid rows only (an invalid estimate is counted,
// not scored); the median of an even count is the mean of the two middle values; p95 is the
// nearest-rank percentile (the ⌈0.95·n⌉-th smallest).
#pragma once

#include <string>
#include <vector>

#include "scene/truth.h"
#include "skypole/estimate.h"

namespace skypol::skypole {

struct EvaluationRow {
  std::string dataset;    // e.g. the stack's file name
  PoleEstimate estimate;  // estimate.method names the method
  scene::Truth truth;    // the stack's truth (frame 0)
};

struct Stats {
  int n = 0;
  double mean = 0, median = 0, p95 = 0, max = 0;
};
Stats summarize_values(std::vector<double> values);  // n = 0 and zeros for no values

struct MethodSummary {
  std::string method;
  int rows = 0;
  int valid = 0;
  Stats bearing_abs_deg;   // over the valid rows with a defined bearing
  Stats latitude_abs_deg;
  Stats angular_deg;
  double mean_seconds = 0;  // over all rows
};

// One summary per method, in order of first appearance.
std::vector<MethodSummary> summarize(const std::vector<EvaluationRow>& rows);

}  // namespace skypol::skypole
