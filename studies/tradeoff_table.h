// The tables `skypol tradeoff` writes: named columns, rows of cells, CSV out. A study fills one
// table per question; scripts/benchmarks reads them back for the plots and the report.
// CSV: RFC 4180 quoting, '.' decimals, numbers with 6 significant digits; a value that is not
// finite (an invalid estimate's error, a rate over no time) is an empty field, never NaN.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace skypol::studies::tradeoff {

class Table {
 public:
  explicit Table(std::vector<std::string> columns);

  // Starts a new row; set() fills its cells by column name (unknown names throw
  // std::logic_error: a typo in a study must not write a silently empty column).
  Table& row();
  Table& set(const std::string& column, double value);
  Table& set(const std::string& column, int value);
  Table& set(const std::string& column, const std::string& value);
  Table& set(const std::string& column, const char* value) { return set(column, std::string(value)); }
  Table& set(const std::string& column, bool value) { return set(column, value ? 1 : 0); }

  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t size() const { return rows_.size(); }
  std::string csv() const;

  // Writes csv() to `path` through a temporary name (nothing half-written is left behind).
  void write(const std::string& path) const;

 private:
  std::size_t index(const std::string& column) const;
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> rows_;
};

// Wall-clock seconds of the fastest of `repeats` calls of f: the machine is shared, and the
// minimum is the figure least disturbed by other work.
template <class F>
double best_seconds(int repeats, F&& f) {
  double best = 0;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (i == 0 || s < best) best = s;
  }
  return best;
}

}  // namespace skypol::studies::tradeoff
