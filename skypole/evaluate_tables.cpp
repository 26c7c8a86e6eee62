// The CSV and text tables of an evaluation (evaluate_tables.h).
#include "skypole/evaluate_tables.h"

#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

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
std::string rows_csv(const std::vector<EvaluationRow>& rows) {
  std::ostringstream os;
  os << "dataset,method,valid,why_invalid,heading_deg,latitude_deg,azimuth_rel_deg,altitude_deg,"
        "is_north,true_heading_deg,true_latitude_deg,bearing_error_deg,latitude_error_deg,"
        "angular_error_deg,residual_deg,sigma_bearing_deg,sigma_latitude_deg,cone95_deg,sigma_deg,"
        "seconds,note\n";
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
         << num(sc->angular_error_deg) << ',' << num(e.residual_deg) << ','
         << num(e.sigma_bearing_deg) << ',' << num(e.sigma_latitude_deg) << ',' << num(e.cone95_deg)
         << ',' << num(e.sigma_deg) << ',';
    else
      os << ",,,,,,,,";
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
