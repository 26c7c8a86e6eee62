// Scoring many rows and writing them out (evaluate.h).
#include "skypole/evaluate.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "skypole/classic.h"
#include "skypole/great_circle.h"
#include "skypole/invariance.h"
#include "skypole/sun_vector.h"

namespace skypol::skypole {
namespace {


std::string num(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream os;
  os << std::setprecision(10) << v;
  return os.str();
}

std::string num(const std::optional<double>& v) { return v ? num(*v) : std::string(); }

}  // namespace

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = {"classic", "great_circle", "invariance",
                                                 "sun_vector", "sun_vector_ephemeris",
                                                 "sun_dolp"};
  return names;
}

PoleEstimate run_method(const stack::Stack& stack, std::string_view method,
                        const InputOptions& input) {
  if (method == "classic") {
    ClassicParams p;
    p.input = input;
    return estimate_classic(stack, p).estimate;
  }
  if (method == "great_circle") {
    GreatCircleParams p;
    p.input = input;
    return estimate_great_circle(stack, p).estimate;
  }
  if (method == "invariance") {
    InvarianceParams p;
    p.input = input;
    return estimate_invariance(stack, p).estimate;
  }
  if (method == "sun_vector" || method == "sun_vector_ephemeris" || method == "sun_dolp") {
    SunVectorParams p;
    p.input = input;
    p.mode = method == "sun_vector_ephemeris" ? PoleFromSun::ephemeris : PoleFromSun::circle;
    p.source = method == "sun_dolp" ? SunSource::dolp : SunSource::aolp;
    PoleEstimate e = estimate_sun_vector(stack, p).estimate;
    e.method = std::string(method);
    return e;
  }
  std::string legal;
  for (const auto& n : method_names()) legal += (legal.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown estimator \"" + std::string(method) +
                              "\" (expected one of " + legal + ")");
}

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

std::string rows_csv(const std::vector<EvaluationRow>& rows) {
  std::ostringstream os;
  os << "dataset,method,valid,why_invalid,heading_deg,latitude_deg,azimuth_rel_deg,altitude_deg,"
        "is_north,true_heading_deg,true_latitude_deg,bearing_error_deg,latitude_error_deg,"
        "angular_error_deg,residual_deg,confidence,seconds,note\n";
  for (const auto& r : rows) {
    const PoleEstimate& e = r.estimate;
    os << csv_field(r.dataset) << ',' << csv_field(e.method) << ',' << (e.valid ? 1 : 0) << ','
       << csv_field(e.why_invalid) << ',';
    std::optional<Score> sc;
    if (e.valid) sc = score(e, r.truth);
    if (e.valid)
      os << num(e.heading_deg) << ',' << num(e.latitude_deg) << ',' << num(e.azimuth_rel_deg) << ','
         << num(e.altitude_deg) << ',' << (e.is_north ? 1 : 0) << ',';
    else
      os << ",,,,,";
    os << num(r.truth.heading_deg) << ',' << num(r.truth.site.latitude_deg) << ',';
    if (sc)
      os << num(sc->bearing_error_deg) << ',' << num(sc->latitude_error_deg) << ','
         << num(sc->angular_error_deg) << ',' << num(e.residual_deg) << ',' << num(e.confidence)
         << ',';
    else
      os << ",,,,,";
    os << num(e.seconds) << ',' << csv_field(e.note) << '\n';
  }
  return os.str();
}

std::string summary_csv(const std::vector<MethodSummary>& summaries) {
  std::ostringstream os;
  os << "method,rows,valid";
  for (const char* q : {"bearing", "latitude", "angular"})
    for (const char* f : {"n", "mean", "median", "p95", "max"}) os << ',' << q << '_' << f;
  os << ",mean_seconds\n";
  for (const auto& s : summaries) {
    os << csv_field(s.method) << ',' << s.rows << ',' << s.valid;
    for (const Stats* st : {&s.bearing_abs_deg, &s.latitude_abs_deg, &s.angular_deg})
      os << ',' << st->n << ',' << num(st->mean) << ',' << num(st->median) << ',' << num(st->p95)
         << ',' << num(st->max);
    os << ',' << num(s.mean_seconds) << '\n';
  }
  return os.str();
}

std::string summary_text(const std::vector<MethodSummary>& summaries) {
  std::ostringstream os;
  os << std::left << std::setw(22) << "method" << std::right << std::setw(7) << "valid"
     << std::setw(12) << "|bearing|" << std::setw(10) << "p95" << std::setw(12) << "|lat|"
     << std::setw(10) << "p95" << std::setw(12) << "angular" << std::setw(10) << "p95"
     << std::setw(10) << "s/run" << '\n';
  os << std::left << std::setw(22) << "" << std::right << std::setw(7) << ""
     << std::setw(12) << "median deg" << std::setw(10) << "deg" << std::setw(12) << "median deg"
     << std::setw(10) << "deg" << std::setw(12) << "median deg" << std::setw(10) << "deg" << '\n';
  os << std::fixed;
  for (const auto& s : summaries) {
    const auto cell = [&](const Stats& st, double v, int w) {
      if (st.n == 0)
        os << std::setw(w) << "-";
      else
        os << std::setw(w) << std::setprecision(3) << v;
    };
    os << std::left << std::setw(22) << s.method << std::right << std::setw(7)
       << (std::to_string(s.valid) + "/" + std::to_string(s.rows));
    cell(s.bearing_abs_deg, s.bearing_abs_deg.median, 12);
    cell(s.bearing_abs_deg, s.bearing_abs_deg.p95, 10);
    cell(s.latitude_abs_deg, s.latitude_abs_deg.median, 12);
    cell(s.latitude_abs_deg, s.latitude_abs_deg.p95, 10);
    cell(s.angular_deg, s.angular_deg.median, 12);
    cell(s.angular_deg, s.angular_deg.p95, 10);
    os << std::setw(10) << std::setprecision(3) << s.mean_seconds << '\n';
  }
  return os.str();
}

}  // namespace skypol::skypole
