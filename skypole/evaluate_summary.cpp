// The per-method statistics of an evaluation (evaluate_summary.h).
#include "skypole/evaluate_summary.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace skypol::skypole {

Stats summarize_values(std::vector<double> v) {
  Stats s;
  s.n = static_cast<int>(v.size());
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / static_cast<double>(v.size());
  const std::size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  const auto rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(n)));
  s.p95 = v[std::clamp<std::size_t>(rank, 1, n) - 1];
  s.max = v.back();
  return s;
}

std::vector<MethodSummary> summarize(const std::vector<EvaluationRow>& rows) {
  std::vector<std::string> order;
  for (const auto& r : rows)
    if (std::find(order.begin(), order.end(), r.estimate.method) == order.end())
      order.push_back(r.estimate.method);
  std::vector<MethodSummary> out;
  for (const auto& m : order) {
    MethodSummary s;
    s.method = m;
    std::vector<double> b, l, a;
    double secs = 0;
    for (const auto& r : rows) {
      if (r.estimate.method != m) continue;
      ++s.rows;
      secs += r.estimate.seconds;
      if (!r.estimate.valid) continue;
      ++s.valid;
      const Score sc = score(r.estimate, r.truth);
      if (sc.bearing_error_deg) b.push_back(std::abs(*sc.bearing_error_deg));
      l.push_back(std::abs(sc.latitude_error_deg));
      a.push_back(sc.angular_error_deg);
    }
    s.bearing_abs_deg = summarize_values(b);
    s.latitude_abs_deg = summarize_values(l);
    s.angular_deg = summarize_values(a);
    s.mean_seconds = s.rows ? secs / s.rows : 0.0;
    out.push_back(s);
  }
  return out;
}

}  // namespace skypol::skypole
