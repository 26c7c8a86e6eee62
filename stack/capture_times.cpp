#include "stack/capture_times.h"

#include <cctype>
#include <cstdio>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <vector>

#include "scene/scene_error.h"

namespace skypol::stack {
namespace {

struct Fields {
  std::string year, month, day, hour, minute, second;  // second with its fraction
};

bool digits(const std::string& s, std::size_t at, std::size_t n) {
  if (at + n > s.size()) return false;
  for (std::size_t i = at; i < at + n; ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  return true;
}

// Backtracking match of format[f..] against name[n..]; fills `out` on success.
bool match(const std::string& fmt, std::size_t f, const std::string& name, std::size_t n, Fields& out) {
  if (f == fmt.size()) return n == name.size();
  if (fmt[f] == '*') {
    for (std::size_t k = n; k <= name.size(); ++k) {
      Fields trial = out;
      if (match(fmt, f + 1, name, k, trial)) {
        out = trial;
        return true;
      }
    }
    return false;
  }
  if (fmt[f] == '%' && f + 1 < fmt.size() && fmt[f + 1] != '%') {
    const char c = fmt[f + 1];
    if (std::string("YmdHMS").find(c) == std::string::npos) {
      throw std::invalid_argument(std::string("time format: unknown field %") + c + " (expected %Y %m %d %H %M %S)");
    }
    const std::size_t width = c == 'Y' ? 4 : 2;
    if (!digits(name, n, width)) return false;
    // Where the field may end: after its digits, or (%S) after a fraction ".d", ".dd", …, longest first.
    std::vector<std::size_t> ends{n + width};
    if (c == 'S' && n + width < name.size() && (name[n + width] == '.' || name[n + width] == ',')) {
      for (std::size_t e = n + width + 1; e < name.size() && std::isdigit(static_cast<unsigned char>(name[e])); ++e) {
        ends.insert(ends.begin(), e + 1);
      }
    }
    for (std::size_t stop : ends) {
      Fields trial = out;
      std::string& field = c == 'Y' ? trial.year : c == 'm' ? trial.month : c == 'd' ? trial.day
                         : c == 'H' ? trial.hour : c == 'M' ? trial.minute : trial.second;
      field = name.substr(n, stop - n);
      if (match(fmt, f + 2, name, stop, trial)) {
        out = trial;
        return true;
      }
    }
    return false;
  }
  const std::size_t step = fmt[f] == '%' ? 2 : 1;  // "%%" is a literal '%'
  if (n < name.size() && name[n] == fmt[f + step - 1]) return match(fmt, f + step, name, n + 1, out);
  return false;
}

sky::Instant with_zone(const std::string& local, const std::string& zone) {
  return sky::parse_iso8601(local + zone);
}

}  // namespace

sky::Instant time_from_name(const std::string& file_name, const std::string& format, const std::string& zone) {
  Fields f;
  if (!match(format, 0, file_name, 0, f)) {
    throw std::invalid_argument("the file name '" + file_name + "' does not match the time format '" + format + "'");
  }
  if (f.year.empty() || f.month.empty() || f.day.empty() || f.hour.empty() || f.minute.empty()) {
    throw std::invalid_argument("the time format '" + format + "' needs at least %Y %m %d %H %M");
  }
  const std::string second = f.second.empty() ? "00" : f.second;
  return with_zone(f.year + "-" + f.month + "-" + f.day + "T" + f.hour + ":" + f.minute + ":" + second, zone);
}

sky::Instant time_from_exif(const std::string& exif, const std::string& zone) {
  // "YYYY:MM:DD HH:MM:SS[.fff]": the date's colons become dashes.
  if (exif.size() < 19 || exif[4] != ':' || exif[7] != ':' || exif[10] != ' ') {
    throw std::invalid_argument("EXIF time '" + exif + "' is not of the form YYYY:MM:DD HH:MM:SS");
  }
  std::string iso = exif;
  iso[4] = iso[7] = '-';
  iso[10] = 'T';
  return with_zone(iso, zone);
}

std::map<std::string, sky::Instant> read_times_csv(const std::string& path, const std::string& zone) {
  std::ifstream in(path);
  if (!in) throw scene::SceneError(scene::FileLoc{path, 0, 0}, "cannot open the times CSV");
  std::map<std::string, sky::Instant> times;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#' || (number == 1 && line == "file,time")) continue;
    const std::size_t comma = line.find(',');
    if (comma == std::string::npos) {
      throw scene::SceneError(scene::FileLoc{path, number, 1}, "expected 'file,time', got '" + line + "'");
    }
    const std::string file = line.substr(0, comma), text = line.substr(comma + 1);
    sky::Instant t;
    try {
      t = sky::parse_iso8601(text);
    } catch (const std::invalid_argument&) {
      try {
        t = with_zone(text, zone);  // a time without its own zone takes the capture's
      } catch (const std::invalid_argument& e) {
        throw scene::SceneError(scene::FileLoc{path, number, static_cast<int>(comma) + 2}, e.what());
      }
    }
    if (!times.emplace(file, t).second) {
      throw scene::SceneError(scene::FileLoc{path, number, 1}, "'" + file + "' is listed twice");
    }
  }
  return times;
}

}  // namespace skypol::stack
