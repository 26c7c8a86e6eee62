// The estimators' registry (method_registry.h).
#include "skypole/method_registry.h"

#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "stack/frame.h"

namespace skypol::skypole {
namespace {

struct Registry {
  std::vector<Method> methods;
  std::vector<std::string> names;  // the methods' and "auto"
};

void add(Registry& r, Method m) {
  if (m.name.empty() || m.name == "auto" || m.name == "all")
    throw std::invalid_argument("register_method: \"" + m.name + "\" cannot name a method");
  for (const Method& o : r.methods)
    if (o.name == m.name) throw std::invalid_argument("register_method: \"" + m.name + "\" is registered already");
  if (!m.bare) throw std::invalid_argument("register_method: " + m.name + " has no bare run");
  m.calibration.method = m.name;
  r.methods.push_back(std::move(m));
  r.names.clear();
  for (const Method& o : r.methods) r.names.push_back(o.name);
  r.names.push_back("auto");
}

Registry& registry() {
  static Registry r = [] {
    Registry built;
#define SKYPOL_METHOD(name) add(built, name##_method());
#include "skypole/method_list.h"
#undef SKYPOL_METHOD
    return built;
  }();
  return r;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The shortest text that reads back as v (0.2, not 0.20000000000000001); null for an unbounded gate.
std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, end);
}

}  // namespace

const std::vector<Method>& methods() { return registry().methods; }

const Method* find_method(std::string_view name) {
  for (const Method& m : registry().methods)
    if (m.name == name) return &m;
  return nullptr;
}

const Method& method_entry(std::string_view name) {
  if (const Method* m = find_method(name)) return *m;
  throw std::invalid_argument("unknown estimator \"" + std::string(name) + "\" (expected one of " +
                              method_names_list() + ")");
}

bool register_method(Method m) {
  add(registry(), std::move(m));
  return true;
}

const std::vector<std::string>& method_names() { return registry().names; }

std::string method_names_list() {
  std::string list;
  for (const std::string& n : method_names()) list += (list.empty() ? "" : ", ") + n;
  return list;
}

bool site_usable(const stack::Stack& stack, const InputOptions& input) { return stack.site_known && input.use_site; }

bool parse_site_use(std::string_view value) {
  if (value == "stack") return true;
  if (value == "unknown") return false;
  throw std::invalid_argument("--site: \"" + std::string(value) + "\" (expected stack or unknown)");
}

std::string methods_json() {
  std::ostringstream os;
  os << "[";
  for (std::size_t i = 0; i < methods().size(); ++i) {
    const Method& m = methods()[i];
    const MethodTraits& t = m.traits;
    const MethodCalibration& c = m.calibration;
    const auto flag = [](bool b) { return b ? "true" : "false"; };
    os << (i ? ",\n " : "\n ") << "{\"name\": " << json_string(m.name)
       << ", \"description\": " << json_string(m.description)
       << ", \"frame_jackknife_max_groups\": " << t.frame_jackknife_max_groups
       << ", \"sector_jackknife\": " << flag(t.sector_jackknife) << ", \"used_by_auto\": " << flag(t.used_by_auto)
       << ", \"needs_site\": " << flag(t.needs_site) << ", \"misfit_measured\": " << flag(t.misfit_measured)
       << ", \"auto_answers_alone\": " << flag(t.auto_answers_alone)
       << ",\n  \"calibration\": {";
    bool first = true;
    for (const auto& [name, field] : calibration_fields()) {
      os << (first ? "" : ", ") << '"' << name << "\": " << json_number(c.*field);
      first = false;
    }
    os << "}}";
  }
  os << "\n]\n";
  return os.str();
}

}  // namespace skypol::skypole
