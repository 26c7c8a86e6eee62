// Estimate north on a stack and print the estimate beside the truth in its headers.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "skypole/estimate.h"

namespace skypol::skypole {

struct EstimateRequest {
  std::string path;
  std::vector<std::string> methods{"classic"};  // names of method_names(), or "all"
  InputOptions input;
  bool json = false;
  std::string intermediates;  // classic only: write its step images to this EXR (empty: none)
  // The picture of the answers (skypole/estimate_plot.h write_estimate_plots: a PNG, or a folder of
  // one PNG per method); written also when every method declined. Empty: none.
  std::string plot;
  // Feedback for a terminal (may be empty): progress(i, n) before method i runs and (n, n) after
  // the last; before_output() before each method's result is printed.
  std::function<void(std::size_t, std::size_t)> progress;
  std::function<void()> before_output;
  // Where the process's time and memory go (`skypol estimate --profile`): a line on stderr for
  // reading the stack (the decode of the channels the estimators read) and for each method, with
  // its wall and CPU seconds and the process's peak resident memory so far (ProcessUsage).
  bool profile = false;
};

// The process's clock and memory at one moment (getrusage and the monotonic clock): differences
// of two say what a stage cost, whatever threads it ran on.
struct ProcessUsage {
  double wall_s = 0, user_s = 0, system_s = 0;
  double max_rss_mib = 0;  // peak resident set since the process started
};
ProcessUsage process_usage();
// "profile STAGE wall_s=… cpu_s=… user_s=… sys_s=… max_rss_mib=…" of the stage between `from`
// and `to`: one line, for people and for scripts (scripts/bench-estimate).
std::string profile_line(const std::string& stage, const ProcessUsage& from, const ProcessUsage& to);

// Prints a table (or JSON: always an array, one object per method with the same keys, declined or
// not; a declined method's reason is printed in the table too). Throws std::invalid_argument on
// bad input (unknown method, unreadable stack) and when every method declined.
void print_estimate(const EstimateRequest& request);
inline void print_estimate(const std::string& path, const std::string& method, bool json) {
  EstimateRequest r;
  r.path = path;
  r.methods = {method};
  r.json = json;
  print_estimate(r);
}

// The channels the estimators read of a stack, and no others (S1, S2 and the other bands are never
// decoded): of the band they pick (`input.band`, else B, else the stack's first) its DoLP and AoLP,
// its S0 (the sky mask's saturated and dark tests, sky_mask.h) and the mask and clipped channels
// (the pixels a sensor clipped, which the calibration's clipped share reads) where the stack has
// them. The in-memory stacks of the studies hold the same, so a user's answer is the study's.
std::vector<std::string> estimator_channels(const std::string& path, const InputOptions& input = {});

// "all" → every method; otherwise checked against method_names().
std::vector<std::string> expand_methods(const std::vector<std::string>& names);

}  // namespace skypol::skypole
