#include "studies/tradeoff_scoring.h"

#include <cmath>
#include <stdexcept>

#include "skypole/estimate.h"
#include "skypole/evaluate.h"

namespace skypol::studies::tradeoff {

const std::vector<std::string>& score_columns() {
  static const std::vector<std::string> c = {"method",            "valid",
                                             "angular_error_deg", "bearing_error_deg",
                                             "latitude_error_deg", "estimate_s",
                                             "why_invalid"};
  return c;
}

std::vector<std::string> with_score_columns(std::vector<std::string> first) {
  first.insert(first.end(), score_columns().begin(), score_columns().end());
  return first;
}

void score_every_method(const stack::Stack& stack, Table& table,
                        const std::function<void(Table&)>& setting) {
  std::vector<skypole::PoleEstimate> done;  // auto (last) combines these, running nothing again
  for (const std::string& m : skypole::method_names()) {
    table.row();
    setting(table);
    skypole::PoleEstimate e;
    double s = 0;
    try {
      s = best_seconds(1, [&] {
        e = m == "auto" ? skypole::combine_estimates(stack, {}, done) : skypole::run_method(stack, m);
      });
      if (m == "auto") s = e.seconds;
    } catch (const std::invalid_argument& error) {  // input this method cannot use (too few frames)
      e.method = m;
      e.valid = false;
      e.why_invalid = error.what();
    }
    done.push_back(e);
    table.set("method", m).set("valid", e.valid).set("estimate_s", s);
    if (!e.valid) {
      table.set("why_invalid", e.why_invalid);
      continue;
    }
    const skypole::Score score = skypole::score(e, stack.frames.front().truth);
    table.set("angular_error_deg", score.angular_error_deg)
        .set("latitude_error_deg", std::abs(score.latitude_error_deg));
    if (score.bearing_error_deg) table.set("bearing_error_deg", std::abs(*score.bearing_error_deg));
  }
}

}  // namespace skypol::studies::tradeoff
