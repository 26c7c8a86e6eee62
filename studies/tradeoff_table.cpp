#include "studies/tradeoff_table.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "skypole/evaluate.h"

namespace skypol::studies::tradeoff {
using skypole::csv_field;

Table::Table(std::vector<std::string> columns) : columns_(std::move(columns)) {}

Table& Table::row() {
  rows_.emplace_back(columns_.size());
  return *this;
}

std::size_t Table::index(const std::string& column) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i] == column) return i;
  throw std::logic_error("tradeoff table has no column \"" + column + "\"");
}

Table& Table::set(const std::string& column, const std::string& value) {
  if (rows_.empty()) throw std::logic_error("tradeoff table: set() before row()");
  rows_.back()[index(column)] = value;
  return *this;
}

Table& Table::set(const std::string& column, int value) { return set(column, std::to_string(value)); }

Table& Table::set(const std::string& column, double value) {
  if (!std::isfinite(value)) return set(column, std::string());
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", value);
  return set(column, std::string(buf));
}

std::string Table::csv() const {
  std::string out;
  for (std::size_t i = 0; i < columns_.size(); ++i) out += (i ? "," : "") + skypole::csv_field(columns_[i]);
  out += "\n";
  for (const auto& r : rows_) {
    for (std::size_t i = 0; i < r.size(); ++i) out += (i ? "," : "") + skypole::csv_field(r[i]);
    out += "\n";
  }
  return out;
}

void Table::write(const std::string& path) const {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    f << csv();
    if (!f.flush()) {
      std::filesystem::remove(tmp);
      throw std::runtime_error("cannot write " + path);
    }
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace skypol::studies::tradeoff
