#include "scene/toml_fields.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace skypol::scene {
namespace {

std::string format_number(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    default: return "a date/time";
  }
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + ("'" + v[i] + "'");
  return out;
}

}  // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diag = up;
    }
  }
  return row[b.size()];
}

Fields::Fields(const toml::table& table, std::string file, std::string path)
    : table_(&table), file_(std::move(file)), path_(std::move(path)) {}

bool Fields::has(std::string_view key) const { return table_->contains(key); }

std::string Fields::dotted(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

FileLoc Fields::loc(std::string_view key) const {
  const toml::node* n = table_->get(key);
  const toml::source_region& src = n ? n->source() : table_->source();
  // A node merged in from an included file or a --set override carries its own origin.
  const std::string& file = src.path && !src.path->empty() ? *src.path : file_;
  // The root of a scene assembled from includes has no source region: a key missing there (a
  // whole section) is reported at the file's first line, so that every error has a line.
  if (src.begin.line == 0) return FileLoc{file, 1, 1};
  return FileLoc{file, static_cast<int>(src.begin.line), static_cast<int>(src.begin.column)};
}

void Fields::fail(std::string_view key, const std::string& message) const {
  throw SceneError(loc(key), "key '" + dotted(key) + "': " + message);
}

const toml::node& Fields::require(std::string_view key, std::string_view expected) {
  used_.insert(std::string(key));
  const toml::node* n = table_->get(key);
  if (!n) {
    throw SceneError(loc(key), "missing key '" + dotted(key) + "' (expected " + std::string(expected) + ")");
  }
  return *n;
}

std::optional<double> Fields::optional_number(std::string_view key, double lo, double hi) {
  if (!has(key)) {
    used_.insert(std::string(key));
    return std::nullopt;
  }
  return required_number(key, lo, hi);
}

double Fields::required_number(std::string_view key, double lo, double hi) {
  const toml::node& n = require(key, "a number");
  std::optional<double> v = n.value<double>();  // integers convert
  if (!n.is_number() || !v) fail(key, "expected a number, found " + type_name(n));
  if (!std::isfinite(*v) || *v < lo || *v > hi) {
    fail(key, "value " + format_number(*v) + " out of range [" + format_number(lo) + ", " + format_number(hi) + "]");
  }
  return *v;
}

double Fields::number(std::string_view key, double fallback, double lo, double hi) {
  return optional_number(key, lo, hi).value_or(fallback);
}

long long Fields::integer(std::string_view key, long long fallback, long long lo, long long hi) {
  if (!has(key)) {
    used_.insert(std::string(key));
    return fallback;
  }
  const toml::node& n = require(key, "an integer");
  if (!n.is_integer()) fail(key, "expected an integer, found " + type_name(n));
  const long long v = *n.value<long long>();
  if (v < lo || v > hi) {
    fail(key, "value " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return v;
}

bool Fields::boolean(std::string_view key, bool fallback) {
  if (!has(key)) {
    used_.insert(std::string(key));
    return fallback;
  }
  const toml::node& n = require(key, "true or false");
  if (!n.is_boolean()) fail(key, "expected true or false, found " + type_name(n));
  return *n.value<bool>();
}

std::optional<std::string> Fields::optional_string(std::string_view key) {
  if (!has(key)) {
    used_.insert(std::string(key));
    return std::nullopt;
  }
  return required_string(key);
}

std::string Fields::required_string(std::string_view key) {
  const toml::node& n = require(key, "a string");
  if (!n.is_string()) fail(key, "expected a string, found " + type_name(n));
  return *n.value<std::string>();
}

std::string Fields::string(std::string_view key, std::string fallback) {
  return optional_string(key).value_or(std::move(fallback));
}

std::string Fields::choice(std::string_view key, std::string fallback, const std::vector<std::string>& legal) {
  std::string v = string(key, std::move(fallback));
  if (std::find(legal.begin(), legal.end(), v) == legal.end()) {
    fail(key, "unknown value '" + v + "' (expected one of " + join(legal) + ")");
  }
  return v;
}

std::vector<std::string> Fields::strings(std::string_view key, std::vector<std::string> fallback) {
  if (!has(key)) {
    used_.insert(std::string(key));
    return fallback;
  }
  const toml::node& n = require(key, "an array of strings");
  const toml::array* a = n.as_array();
  if (!a) fail(key, "expected an array of strings, found " + type_name(n));
  std::vector<std::string> out;
  for (const toml::node& e : *a) {
    if (!e.is_string()) fail(key, "expected an array of strings, found an element that is " + type_name(e));
    out.push_back(*e.value<std::string>());
  }
  return out;
}

std::vector<double> Fields::numbers(std::string_view key, std::vector<double> fallback) {
  if (!has(key)) {
    used_.insert(std::string(key));
    return fallback;
  }
  const toml::node& n = require(key, "an array of numbers");
  const toml::array* a = n.as_array();
  if (!a) fail(key, "expected an array of numbers, found " + type_name(n));
  std::vector<double> out;
  for (const toml::node& e : *a) {
    if (!e.is_number()) fail(key, "expected an array of numbers, found an element that is " + type_name(e));
    out.push_back(*e.value<double>());
  }
  return out;
}

std::vector<Fields::Row> Fields::rows(std::string_view key, std::size_t width) {
  used_.insert(std::string(key));
  std::vector<Row> out;
  const toml::node* n = table_->get(key);
  if (!n) return out;
  const std::string expected = "an array of [" + std::to_string(width) + " numbers] rows";
  const toml::array* a = n->as_array();
  if (!a) fail(key, "expected " + expected + ", found " + type_name(*n));
  for (const toml::node& e : *a) {
    const toml::array* row = e.as_array();
    if (!row || row->size() != width) fail(key, "expected " + expected + ", found a row that is not");
    Row r;
    for (const toml::node& x : *row) {
      if (!x.is_number()) fail(key, "expected " + expected + ", found an element that is " + type_name(x));
      r.push_back(*x.value<double>());
    }
    out.push_back(std::move(r));
  }
  return out;
}

const toml::node* Fields::node(std::string_view key) {
  used_.insert(std::string(key));
  return table_->get(key);
}

std::optional<Fields> Fields::table(std::string_view key) {
  used_.insert(std::string(key));
  const toml::node* n = table_->get(key);
  if (!n) return std::nullopt;
  if (!n->is_table()) fail(key, "expected a table, found " + type_name(*n));
  return Fields(*n->as_table(), file_, dotted(key));
}

std::vector<Fields> Fields::tables(std::string_view key) {
  used_.insert(std::string(key));
  std::vector<Fields> out;
  const toml::node* n = table_->get(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables()) fail(key, "expected an array of tables ([[" + dotted(key) + "]])");
  std::size_t i = 0;
  for (const toml::node& element : *a) {
    out.emplace_back(*element.as_table(), file_, dotted(key) + "[" + std::to_string(i++) + "]");
  }
  return out;
}

void Fields::finish() const {
  for (const auto& [k, node] : *table_) {
    const std::string_view name = k.str();
    if (used_.count(name)) continue;
    std::string best;
    std::size_t best_d = 3;  // suggest only plausible typos
    for (const std::string& known : used_) {
      const std::size_t d = edit_distance(name, known);
      if (d < best_d) best_d = d, best = known;
    }
    std::string msg = "unknown key '" + dotted(name) + "'";
    if (!best.empty()) msg += " (did you mean '" + dotted(best) + "'?)";
    const auto& src = k.source().begin ? k.source() : node.source();
    const std::string& file = src.path && !src.path->empty() ? *src.path : file_;
    throw SceneError(FileLoc{file, static_cast<int>(src.begin.line), static_cast<int>(src.begin.column)}, msg);
  }
}

}  // namespace skypol::scene
