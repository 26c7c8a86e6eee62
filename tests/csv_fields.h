// One CSV line into fields, as the tradeoff tables and `evaluate` write them (RFC 4180 quoting:
// "a, b" is one field, "" inside quotes is "). Shared by the tests that read those tables.
#pragma once

#include <string>
#include <vector>

namespace skypol::test {

inline std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      out.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}

}  // namespace skypol::test
