// A JSON string literal for the project's machine-readable outputs (manifest.jsonl, `--json`).
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace skypol::scene {

// `s` quoted for JSON: " and \ escaped, control characters as \u00XX; other bytes (UTF-8) kept.
inline std::string json_quoted(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace skypol::scene
