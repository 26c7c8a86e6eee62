// How the sky's spec checks word their errors, so the scene loader can point at the key: every
// message starts with the field's dotted name ("sky.aerosol.tau_550: …") and states the value.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace skypol::sky {

// A value as the messages print it (shortest form the stream gives, e.g. 0.1, 1e-06).
inline std::string spec_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Throws std::invalid_argument("<field>: <message>"); field is the whole dotted name.
[[noreturn]] inline void spec_error(const std::string& field, const std::string& message) {
  throw std::invalid_argument(field + ": " + message);
}

}  // namespace skypol::sky
