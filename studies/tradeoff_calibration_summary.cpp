// The calibration study's summaries (tradeoff_calibration.h, write_summaries): per method and per
// method and sky model, the yield, lies, coverage with its Wilson interval and the error
// distribution; and auto against each method on the scenes both answer.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "skypole/sky_images.h"
#include "skypole/uncertainty.h"
#include "studies/tradeoff_calibration.h"
#include "studies/tradeoff_table.h"

namespace skypol::studies::tradeoff::calibration {
namespace {

// The q-quantile of v by rank ⌈q·n⌉ (the smallest value with at least q of them at or below it);
// NaN (an empty field) for no values.
double quantile(std::vector<double> v, double q) {
  return v.empty() ? std::nan("") : skypole::quantile(std::move(v), q, skypole::QuantileRank::nearest);
}

// One row of t for method m over the scenes of one sky model (every scene: sky empty, the row of
// calibration_summary.csv, which also says the run's seed, binning and bound).
void fill(Table& t, const std::vector<Outcome>& outcomes, const std::vector<std::string>& methods, std::size_t m,
          const std::string& sky, const StudyOptions& o, int binning) {
  int stacks = 0, valid = 0, lies = 0, inside = 0;
  std::vector<double> errors, ratios;
  for (const Outcome& r : outcomes) {
    if (r.method != m || (!sky.empty() && r.sky != sky)) continue;
    ++stacks;
    if (!r.valid) continue;
    ++valid;
    lies += r.lie ? 1 : 0;
    inside += r.inside ? 1 : 0;
    errors.push_back(r.error);
    ratios.push_back(r.ratio);
  }
  t.row()
      .set("method", methods[m])
      .set("stacks", stacks)
      .set("valid", valid)
      .set("yield", stacks ? static_cast<double>(valid) / stacks : std::nan(""))
      .set("lies", lies)
      .set("lie_rate", valid ? static_cast<double>(lies) / valid : std::nan(""))
      .set("inside_cone", inside)
      .set("coverage", valid ? static_cast<double>(inside) / valid : std::nan(""))
      .set("coverage_low95", skypole::wilson_interval95(inside, valid).first)
      .set("coverage_high95", skypole::wilson_interval95(inside, valid).second)
      .set("median_error_deg", quantile(errors, 0.5))
      .set("p95_error_deg", quantile(errors, 0.95))
      .set("max_error_deg", quantile(errors, 1.0));
  if (sky.empty())
    t.set("p90_error_deg", quantile(errors, 0.9))
        .set("factor_for_95", quantile(ratios, 0.95))
        .set("seed", static_cast<int>(o.seed))
        .set("binning", binning)
        .set("max_uncertainty_deg", o.max_uncertainty_deg);
  else
    t.set("sky", sky);
}

// auto against each method on the scenes where both answer: medians over the same scenes, so that
// auto's wider reach (scenes only one method answers) does not decide the comparison.
Table auto_against_methods(const std::vector<Outcome>& outcomes, const std::vector<std::string>& methods) {
  Table common({"method", "common", "method_median_error_deg", "auto_median_error_deg", "method_only",
                "auto_only"});
  const std::size_t auto_index = methods.size() - 2;
  for (std::size_t m = 0; m < auto_index; ++m) {
    std::vector<double> mine, theirs;
    int method_only = 0, auto_only = 0;
    for (std::size_t k = 0; k < outcomes.size() / methods.size(); ++k) {  // the scenes run
      const Outcome& a = outcomes[k * methods.size() + m];
      const Outcome& b = outcomes[k * methods.size() + auto_index];
      if (a.valid && b.valid) {
        mine.push_back(a.error);
        theirs.push_back(b.error);
      }
      method_only += a.valid && !b.valid ? 1 : 0;
      auto_only += b.valid && !a.valid ? 1 : 0;
    }
    common.row()
        .set("method", methods[m])
        .set("common", static_cast<int>(mine.size()))
        .set("method_median_error_deg", quantile(mine, 0.5))
        .set("auto_median_error_deg", quantile(theirs, 0.5))
        .set("method_only", method_only)
        .set("auto_only", auto_only);
  }
  return common;
}

}  // namespace

void write_summaries(const std::vector<Outcome>& outcomes, const std::vector<std::string>& methods,
                     const StudyOptions& o, int binning) {
  const std::vector<std::string> skies = {"rayleigh", "berry", "vrte"};
  Table summary({"method", "stacks", "valid", "yield", "lies", "lie_rate", "inside_cone", "coverage",
                 "coverage_low95", "coverage_high95", "median_error_deg", "p90_error_deg", "p95_error_deg",
                 "max_error_deg", "factor_for_95", "seed", "binning", "max_uncertainty_deg"});
  // The same per sky model: what a physically based sky (or Berry's neutral points) does to each.
  Table by_sky({"method", "sky", "stacks", "valid", "yield", "lies", "lie_rate", "inside_cone", "coverage",
                "coverage_low95", "coverage_high95", "median_error_deg", "p95_error_deg", "max_error_deg"});
  for (std::size_t m = 0; m < methods.size(); ++m) {
    fill(summary, outcomes, methods, m, "", o, binning);
    for (const std::string& sky : skies) fill(by_sky, outcomes, methods, m, sky, o, binning);
  }
  const std::filesystem::path out(o.out_dir);
  summary.write((out / "calibration_summary.csv").string());
  by_sky.write((out / "calibration_by_sky.csv").string());
  auto_against_methods(outcomes, methods).write((out / "calibration_auto.csv").string());
}

}  // namespace skypol::studies::tradeoff::calibration
