// One table per option enum gives both directions, name → value (for the CLI and scene keys) and
// value → name (for reports), with one error message. Internal to skypole/.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace skypol::skypole {

template <class E, std::size_t N>
using EnumNames = std::array<std::pair<E, std::string_view>, N>;

// "auto" is accepted wherever "automatic" is a name. Throws std::invalid_argument naming `what`,
// the name given and the legal ones.
template <class E, std::size_t N>
E enum_from_name(const EnumNames<E, N>& table, std::string_view name, std::string_view what) {
  const std::string_view key = name == "auto" ? std::string_view("automatic") : name;
  std::string legal;
  for (const auto& [value, n] : table) {
    if (n == key) return value;
    legal += (legal.empty() ? "" : ", ") + std::string(n);
  }
  throw std::invalid_argument("unknown " + std::string(what) + " \"" + std::string(name) +
                              "\" (expected one of " + legal + ")");
}

template <class E, std::size_t N>
std::string_view enum_name(const EnumNames<E, N>& table, E value) {
  for (const auto& [v, n] : table)
    if (v == value) return n;
  return "?";
}

}  // namespace skypol::skypole
