// Typed, checked access to one TOML table of a scene, with errors that name the file, line, column
// and dotted key. Every key read is remembered; finish() turns any key nobody read into an error
// with the nearest known key as a suggestion. This is what makes "unknown keys are errors" hold
// for every section without each section listing its keys twice.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "scene/scene_error.h"

namespace skypol::scene {

class Fields {
 public:
  // `path` is the dotted name of this table ("" for the root), used in messages.
  Fields(const toml::table& table, std::string file, std::string path);

  bool has(std::string_view key) const;

  // Numbers: integers are accepted where a float is expected. Out of [lo, hi] is an error that
  // states the range.
  double number(std::string_view key, double fallback, double lo, double hi);
  double required_number(std::string_view key, double lo, double hi);
  std::optional<double> optional_number(std::string_view key, double lo, double hi);
  long long integer(std::string_view key, long long fallback, long long lo, long long hi);
  bool boolean(std::string_view key, bool fallback);
  std::string string(std::string_view key, std::string fallback);
  std::string required_string(std::string_view key);
  std::optional<std::string> optional_string(std::string_view key);
  // A string that must be one of `legal`; the error lists them.
  std::string choice(std::string_view key, std::string fallback, const std::vector<std::string>& legal);
  std::vector<std::string> strings(std::string_view key, std::vector<std::string> fallback);
  std::vector<double> numbers(std::string_view key, std::vector<double> fallback);
  // An array of `width`-number arrays, e.g. a table = [[0, 0.0], [10, 0.31]].
  using Row = std::vector<double>;
  std::vector<Row> rows(std::string_view key, std::size_t width);

  // Any value, marked as read (nullptr when absent), for a key that accepts several types; the
  // caller checks the type and reports with fail().
  const toml::node* node(std::string_view key);

  // A sub-table; nullopt if absent. The sub-table's keys are checked by its own Fields.
  std::optional<Fields> table(std::string_view key);
  // Array of tables ([[occluders.box]]).
  std::vector<Fields> tables(std::string_view key);

  // Error at a key (or at the table if the key is absent), with this file and location.
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;
  FileLoc loc(std::string_view key) const;
  std::string dotted(std::string_view key) const;

  // Throws for the first key in this table that was never read.
  void finish() const;

  const toml::table& raw() const { return *table_; }
  const std::string& file() const { return file_; }

 private:
  const toml::node& require(std::string_view key, std::string_view expected);
  const toml::table* table_;
  std::string file_;
  std::string path_;
  std::set<std::string, std::less<>> used_;
};

// Levenshtein distance, for "did you mean" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);

}  // namespace skypol::scene
