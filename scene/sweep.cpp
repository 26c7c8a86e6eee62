#include "scene/sweep.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "camera/camera.h"
#include "scene/json_text.h"
#include "scene/toml_fields.h"
#include "scene/truth.h"

namespace skypol::scene {
namespace {

namespace fs = std::filesystem;
FileLoc loc_of(const toml::node& node, const std::string& file) {
  const toml::source_region& src = node.source();
  return FileLoc{src.path && !src.path->empty() ? *src.path : file, static_cast<int>(src.begin.line),
                 static_cast<int>(src.begin.column)};
}

// A number as TOML: integers as written, floats to 12 significant digits (so that a range of
// 0.1 steps gives 0.3, not 0.30000000000000004), always with a '.' or an exponent.
std::string number_text(double v, bool integer) {
  char buf[64];
  if (integer) {
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(std::llround(v)));
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%.12g", v);
  std::string s = buf;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string date_of(sky::Instant t) {
  const sky::CalendarUtc c = sky::to_calendar(t);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02d", c.year, c.month, c.day);
  return buf;
}

// A calendar date as midnight UTC (the string of a TOML date value, or a "YYYY-MM-DD" string).
sky::Instant date_at(const Fields& range, std::string_view key) {
  const toml::node* n = range.raw().get(key);
  std::string text;
  if (const auto* d = n ? n->as_date() : nullptr) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02d", d->get().year, d->get().month, d->get().day);
    text = buf;
  } else if (n && n->is_string()) {
    text = *n->value<std::string>();
  }
  if (text.size() != 10) range.fail(key, "expected a date YYYY-MM-DD");
  try {
    return sky::parse_iso8601(text + "T00:00Z");
  } catch (const std::invalid_argument& e) {
    range.fail(key, e.what());
  }
}

// { start, end, step } or { start, end, count } over numbers; { start, end, step_days } over dates.
std::vector<std::string> expand_range(Fields& r) {
  std::vector<std::string> out;
  const toml::node* start = r.node("start");
  const toml::node* end = r.node("end");
  if (!end) r.fail("end", "missing (a range needs start, end and step or count)");
  const bool dates = start->is_date() || start->is_string();
  if (dates) {
    const sky::Instant t0 = date_at(r, "start"), t1 = date_at(r, "end");
    if (t1 < t0) r.fail("end", "is before start");
    const long long step = r.integer("step_days", 1, 1, 100000);
    for (double t = t0.unix_seconds; t <= t1.unix_seconds; t += static_cast<double>(step) * 86400) {
      out.push_back("\"" + date_of(sky::Instant{t}) + "\"");
      if (out.size() > kMaxVariants) r.fail("step_days", "gives more than " + std::to_string(kMaxVariants) + " values");
    }
    r.finish();
    return out;
  }
  if (!start->is_number()) r.fail("start", "a range runs over numbers or dates");
  const double a = r.required_number("start", -1e300, 1e300);
  const double b = r.required_number("end", -1e300, 1e300);
  const bool has_step = r.has("step"), has_count = r.has("count");
  if (has_step == has_count) r.fail(has_step ? "count" : "step", "give either 'step' or 'count'");
  bool integer = start->is_integer() && end->is_integer();
  std::vector<double> values;
  if (has_step) {
    const double step = r.required_number("step", -1e300, 1e300);
    integer = integer && r.raw().get("step")->is_integer();
    if (step == 0 || (b - a) * step < 0) r.fail("step", "must be non-zero and go from start towards end");
    const double n = std::floor((b - a) / step + 1e-9);
    if (n >= static_cast<double>(kMaxVariants)) r.fail("step", "gives more than " + std::to_string(kMaxVariants) + " values");
    for (long long i = 0; i <= static_cast<long long>(n); ++i) values.push_back(a + static_cast<double>(i) * step);
  } else {
    const long long n = r.integer("count", 2, 1, static_cast<long long>(kMaxVariants));
    integer = false;  // evenly spaced values are fractions in general
    for (long long i = 0; i < n; ++i) {
      values.push_back(n == 1 ? a : a + (b - a) * static_cast<double>(i) / static_cast<double>(n - 1));
    }
  }
  r.finish();
  for (double v : values) out.push_back(number_text(v, integer));
  return out;
}

// A table in [axes] is a range when it has a scalar `start`; otherwise its keys continue the
// dotted name (`camera.heading_deg = [...]` written without quotes).
bool is_range(const toml::table& t) {
  const toml::node* s = t.get("start");
  return s && !s->is_array() && !s->is_table();
}

void collect_axes(const toml::table& t, const std::string& prefix, const std::string& file, std::vector<SweepAxis>& out) {
  for (auto&& [k, node] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    SweepAxis axis{key, {}, loc_of(node, file)};
    if (axis.where.line == 0) axis.where = loc_of(t, file);
    if (const toml::array* a = node.as_array()) {
      if (a->empty()) throw SceneError(axis.where, "axis '" + key + "': no values");
      for (const toml::node& e : *a) axis.values.push_back(to_toml_value(e));
    } else if (const toml::table* sub = node.as_table()) {
      if (!is_range(*sub)) {
        collect_axes(*sub, key, file, out);
        continue;
      }
      Fields r(*sub, file, "axes." + key);
      axis.values = expand_range(r);
      if (axis.values.empty()) throw SceneError(axis.where, "axis '" + key + "': the range is empty");
    } else {
      throw SceneError(axis.where, "axis '" + key + "': expected a list of values [a, b, …] or a range "
                                   "{ start, end, step } (write a value that every variant shares in [set])");
    }
    out.push_back(std::move(axis));
  }
}

void collect_set(const toml::table& t, const std::string& prefix, const std::string& file, Sweep& sweep) {
  for (auto&& [k, node] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const toml::table* sub = node.as_table()) {
      collect_set(*sub, key, file, sweep);
      continue;
    }
    sweep.set.push_back(Override{key, to_toml_value(node), ""});
    sweep.set_where.push_back(loc_of(node, file));
  }
}

bool before(const FileLoc& a, const FileLoc& b) { return std::tie(a.line, a.column) < std::tie(b.line, b.column); }

// FNV-1a, 64 bits: a stable name for a variant's merged scene (not for security).
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

// An error raised at an override's origin, moved to the sweep file's entry that made it.
[[noreturn]] void rethrow_at(const SceneError& e, const FileLoc& where, const std::string& what) {
  const std::string full = e.what();
  const std::string prefix = e.where().str() + ": error: ";
  std::string message = full.rfind(prefix, 0) == 0 ? full.substr(prefix.size()) : full;
  throw SceneError(where, message + " (" + what + ")");
}

// JSON for a TOML value (dates and times as strings).
void json_of(std::ostream& os, const toml::node& n) {
  if (const auto* a = n.as_array()) {
    os << "[";
    for (std::size_t i = 0; i < a->size(); ++i) {
      if (i) os << ", ";
      json_of(os, *a->get(i));
    }
    os << "]";
  } else if (const auto* t = n.as_table()) {
    os << "{";
    bool first = true;
    for (auto&& [k, v] : *t) {
      os << (first ? "" : ", ");
      first = false;
      json_of(os, toml::value<std::string>(std::string(k.str())));
      os << ": ";
      json_of(os, v);
    }
    os << "}";
  } else if (n.is_string() || n.is_date() || n.is_time() || n.is_date_time()) {
    std::string s = n.is_string() ? *n.value<std::string>() : to_toml_value(n);
    os << json_quoted(s);
  } else if (n.is_floating_point()) {
    const double v = *n.value<double>();
    if (!std::isfinite(v)) {
      os << "null";  // JSON has no inf or nan; no scene key accepts them anyway
    } else {
      char buf[64];
      os << std::string_view(buf, static_cast<std::size_t>(std::to_chars(buf, buf + sizeof buf, v).ptr - buf));
    }
  } else {
    os << to_toml_value(n);  // integers, booleans: the same in JSON
  }
}

std::string json_value(const std::string& toml_text) {
  const toml::table t = toml::parse("v = " + toml_text);
  std::ostringstream os;
  json_of(os, *t.get("v"));
  return os.str();
}

std::string num(double v) {
  if (v == 0) v = 0;  // no "-0" in the manifest
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace

std::size_t Sweep::size() const {
  std::size_t n = 1;
  for (const SweepAxis& a : axes) n *= a.values.size();
  return n;
}

Sweep parse_sweep(const std::string& text, const std::string& file_name) {
  const toml::table root = parse_toml(text, file_name);
  Fields top(root, file_name, "");
  Sweep sweep;
  sweep.file = file_name;
  fs::path base(top.required_string("base"));
  if (base.is_relative()) base = fs::path(file_name).parent_path() / base;
  sweep.base = base.lexically_normal().string();
  sweep.base_where = top.loc("base");
  if (const toml::node* set = top.node("set")) {
    if (!set->is_table()) top.fail("set", "expected a table of scene keys and values");
    collect_set(*set->as_table(), "", file_name, sweep);
  }
  if (const toml::node* axes = top.node("axes")) {
    if (!axes->is_table()) top.fail("axes", "expected a table of scene keys and their values");
    collect_axes(*axes->as_table(), "", file_name, sweep.axes);
  }
  top.finish();
  // toml++ keeps keys sorted; the grid follows the file's order.
  std::stable_sort(sweep.axes.begin(), sweep.axes.end(),
                   [](const SweepAxis& a, const SweepAxis& b) { return before(a.where, b.where); });
  for (std::size_t i = 0; i < sweep.axes.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (sweep.axes[i].key == sweep.axes[j].key) {
        throw SceneError(sweep.axes[i].where, "axis '" + sweep.axes[i].key + "' is given twice");
      }
    }
    for (const Override& s : sweep.set) {
      if (s.key == sweep.axes[i].key) {
        throw SceneError(sweep.axes[i].where, "axis '" + s.key + "' is also in [set]");
      }
    }
  }
  double n = 1;
  for (const SweepAxis& a : sweep.axes) n *= static_cast<double>(a.values.size());
  if (n > static_cast<double>(kMaxVariants)) {
    top.fail("axes", "the grid has " + fixed(n, 0) + " variants, more than " + std::to_string(kMaxVariants) +
                         ": split it into several sweeps");
  }
  return sweep;
}

Sweep load_sweep(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || fs::is_directory(path)) throw SceneError(FileLoc{path, 0, 0}, "cannot open sweep file");
  std::ostringstream os;
  os << in.rdbuf();
  return parse_sweep(os.str(), path);
}

Variant make_variant(const Sweep& sweep, std::size_t index, const std::vector<Override>& extra) {
  Variant v;
  v.index = index;
  // Mixed radix, the last axis fastest.
  std::vector<std::size_t> pick(sweep.axes.size());
  std::size_t rest = index;
  for (std::size_t i = sweep.axes.size(); i-- > 0;) {
    pick[i] = rest % sweep.axes[i].values.size();
    rest /= sweep.axes[i].values.size();
  }
  // Each override gets its own origin, so that an error can be traced back to its entry.
  std::vector<Override> overrides;
  std::vector<std::pair<FileLoc, std::string>> where;  // parallel to overrides
  for (std::size_t i = 0; i < sweep.set.size(); ++i) {
    overrides.push_back(Override{sweep.set[i].key, sweep.set[i].value, "[set] " + sweep.set[i].key});
    where.emplace_back(sweep.set_where[i], "[set] " + sweep.set[i].key + " = " + sweep.set[i].value);
  }
  for (const Override& o : extra) {
    for (const SweepAxis& a : sweep.axes) {
      if (a.key == o.key) {
        throw SceneError(FileLoc{o.origin, 1, 1}, "key '" + o.key + "': the command line's " + o.origin +
                                                      " cannot set a sweep axis (axis '" + a.key + "' at " +
                                                      a.where.str() + ")");
      }
    }
    overrides.push_back(o);
    where.emplace_back(FileLoc{o.origin, 0, 0}, "");
  }
  for (std::size_t i = 0; i < sweep.axes.size(); ++i) {
    const SweepAxis& a = sweep.axes[i];
    const std::string& value = a.values[pick[i]];
    overrides.push_back(Override{a.key, value, "axis " + a.key});
    where.emplace_back(a.where, "axis '" + a.key + "' = " + value);
    v.params.emplace_back(a.key, value);
  }
  try {
    SceneSource source = load_scene_source(sweep.base, overrides);
    v.scene = scene_from_source(source);
    char name[64];
    std::snprintf(name, sizeof name, "%06zu-%08llx.exr", index,
                  static_cast<unsigned long long>(fnv1a(to_toml(source.root)) & 0xffffffffull));
    v.file = name;
    const std::shared_ptr<const camera::Camera> cam = build_camera(v.scene.camera);
    v.truth = make_truth(v.scene, *cam, v.scene.times.front());
  } catch (const SceneError& e) {
    // The base scene itself cannot be read: that is the sweep file's `base` key.
    if (e.where().file == sweep.base && e.where().line == 0 && sweep.base_where.line > 0) {
      throw SceneError(sweep.base_where, "key 'base': cannot open the base scene '" + sweep.base + "'");
    }
    for (std::size_t i = 0; i < overrides.size(); ++i) {
      if (e.where().file == overrides[i].origin && !where[i].second.empty()) rethrow_at(e, where[i].first, where[i].second);
    }
    throw;
  } catch (const std::invalid_argument& e) {
    // Combinations that only the camera or sky builders catch.
    throw SceneError(FileLoc{sweep.file, 0, 0}, "variant " + std::to_string(index) + ": " + e.what());
  }
  return v;
}

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  auto whole = [](const std::string& s, std::size_t& out) {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) return false;
    out = std::stoul(s);
    return true;
  };
  Shard s;
  if (slash == std::string::npos || !whole(text.substr(0, slash), s.index) || !whole(text.substr(slash + 1), s.count) ||
      s.count == 0) {
    throw std::invalid_argument("--shard " + text + ": expected i/N with whole numbers, 1 <= i <= N (e.g. 2/8)");
  }
  if (s.index < 1 || s.index > s.count) {
    throw std::invalid_argument("--shard " + text + ": shard " + std::to_string(s.index) + " is outside 1.." +
                                std::to_string(s.count));
  }
  return s;
}

std::string manifest_line(const Variant& v) {
  const Truth& t = v.truth;
  std::ostringstream os;
  os << "{\"index\": " << v.index << ", \"file\": \"" << v.file << "\", \"params\": {";
  for (std::size_t i = 0; i < v.params.size(); ++i) {
    os << (i ? ", " : "") << json_value("\"" + v.params[i].first + "\"") << ": " << json_value(v.params[i].second);
  }
  os << "}, \"truth\": {\"latitude_deg\": " << num(t.site.latitude_deg) << ", \"longitude_deg\": "
     << num(t.site.longitude_deg) << ", \"height_m\": " << num(t.site.height_m) << ", \"heading_deg\": "
     << num(t.heading_deg) << ", \"tilt_deg\": " << num(t.tilt_deg) << ", \"roll_deg\": " << num(t.roll_deg)
     << ", \"pole\": \"" << (t.pole_is_north ? "north" : "south") << "\", \"pole_enu\": [" << num(t.pole_enu.x())
     << ", " << num(t.pole_enu.y()) << ", " << num(t.pole_enu.z()) << "], \"pole_pixel\": ";
  if (t.pole_pixel) {
    os << "[" << fixed(t.pole_pixel->x(), 4) << ", " << fixed(t.pole_pixel->y(), 4) << "]";
  } else {
    os << "null";
  }
  os << ", \"frames\": " << v.scene.times.size() << ", \"first_time\": \"" << sky::format_iso8601(v.scene.times.front())
     << "\", \"last_time\": \"" << sky::format_iso8601(v.scene.times.back()) << "\"}}";
  return os.str();
}

}  // namespace skypol::scene
