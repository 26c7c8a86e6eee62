// ISO 8601 instants. The calendar arithmetic is std::chrono's proleptic Gregorian calendar, so
// leap years and month lengths come from the standard library rather than from a table of ours.
#include "sky/time.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <date/tz.h>

namespace skypol::sky {
namespace {

constexpr std::string_view kExpected =
    "expected YYYY-MM-DDThh:mm[:ss[.fff]] ('T' or a space between date and time) followed by a zone: "
    "Z, ±hh:mm, ±hhmm, ±hh or an IANA zone in brackets (e.g. 2022-09-23T10:30:00Z, "
    "2022-09-23 12:30:00+02:00 or 2022-09-23T12:30:00[Europe/Paris])";

[[noreturn]] void fail(std::string_view text, std::string_view problem) {
  throw std::invalid_argument("invalid ISO 8601 instant \"" + std::string(text) + "\": " +
                              std::string(problem) + "; " + std::string(kExpected));
}

// A tiny cursor over the text that reads fixed-width digit fields and literal characters.
class Cursor {
 public:
  explicit Cursor(std::string_view text) : text_(text) {}

  bool done() const { return pos_ == text_.size(); }
  char peek() const { return done() ? '\0' : text_[pos_]; }
  std::size_t pos() const { return pos_; }

  // Exactly `width` decimal digits, named `what` in the error message.
  int digits(int width, std::string_view what) {
    int value = 0;
    for (int i = 0; i < width; ++i) {
      const char c = peek();
      if (c < '0' || c > '9') {
        fail(text_, std::string(what) + " needs " + std::to_string(width) + " digits at position " +
                        std::to_string(pos_ + 1));
      }
      value = value * 10 + (c - '0');
      ++pos_;
    }
    return value;
  }

  void expect(char c, std::string_view what) {
    if (peek() != c) {
      fail(text_, "expected '" + std::string(1, c) + "' " + std::string(what) + " at position " +
                      std::to_string(pos_ + 1));
    }
    ++pos_;
  }

  bool accept(char c) {
    if (peek() != c) return false;
    ++pos_;
    return true;
  }

  // Digits after the decimal point, as a fraction of a second (at least one digit).
  double fraction() {
    double value = 0;
    double scale = 0.1;
    const std::size_t start = pos_;
    while (peek() >= '0' && peek() <= '9') {
      value += scale * (peek() - '0');
      scale *= 0.1;
      ++pos_;
    }
    if (pos_ == start) fail(text_, "a decimal point must be followed by digits");
    return value;
  }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
};

void check_range(std::string_view text, int value, int lo, int hi, std::string_view what) {
  if (value < lo || value > hi) {
    fail(text, std::string(what) + " " + std::to_string(value) + " is outside [" + std::to_string(lo) +
                   ", " + std::to_string(hi) + "]");
  }
}

// Days from 1970-01-01 to a proleptic Gregorian date that has been validated.
long long days_from_civil(int year, int month, int day) {
  using namespace std::chrono;
  const sys_days d{std::chrono::year{year} / std::chrono::month{static_cast<unsigned>(month)} /
                   std::chrono::day{static_cast<unsigned>(day)}};
  return d.time_since_epoch().count();
}

// Local civil seconds (since 1970-01-01T00:00 on the local calendar) in an IANA zone, from the
// system's tz database (Debian's tzdata), as POSIX seconds. A local time the zone skips (clocks
// forward) is an error; one it repeats (clocks back) needs the offset to say which is meant. An
// offset given with the zone must be the zone's offset at that instant.
long long in_zone(std::string_view text, long long local, std::optional<int> offset_minutes, std::string_view name) {
  const date::time_zone* zone = nullptr;
  try {
    zone = date::locate_zone(name);
  } catch (const std::exception&) {
    fail(text, "unknown time zone '" + std::string(name) + "' (expected an IANA name such as Europe/Paris, "
               "from the system's tz database)");
  }
  const date::local_seconds ls{std::chrono::seconds{local}};
  if (offset_minutes) {
    const date::sys_seconds sys{std::chrono::seconds{local - *offset_minutes * 60LL}};
    const auto zone_offset = std::chrono::duration_cast<std::chrono::minutes>(zone->get_info(sys).offset).count();
    if (zone_offset != *offset_minutes) {
      fail(text, "the offset disagrees with " + std::string(name) + ", whose offset then is " +
                     std::to_string(zone_offset) + " min");
    }
    return sys.time_since_epoch().count();
  }
  const date::local_info info = zone->get_info(ls);
  if (info.result == date::local_info::nonexistent) {
    fail(text, "this local time does not exist in " + std::string(name) + " (the clocks jump forward over it)");
  }
  if (info.result == date::local_info::ambiguous) {
    fail(text, "this local time occurs twice in " + std::string(name) +
                   " (the clocks go back): give the offset too, e.g. …+01:00[" + std::string(name) + "]");
  }
  return local - std::chrono::duration_cast<std::chrono::seconds>(info.first.offset).count();
}

}  // namespace

Instant parse_iso8601(std::string_view text) {
  Cursor c(text);
  const int year = c.digits(4, "the year");
  c.expect('-', "between year and month");
  const int month = c.digits(2, "the month");
  c.expect('-', "between month and day");
  const int day = c.digits(2, "the day");
  if (!(c.accept('T') || c.accept('t') || c.accept(' '))) {
    fail(text, "expected 'T' or a space after the date at position " + std::to_string(c.pos() + 1));
  }
  const int hour = c.digits(2, "the hour");
  c.expect(':', "between hour and minute");
  const int minute = c.digits(2, "the minute");
  int second = 0;
  double fraction = 0;
  if (c.accept(':')) {
    second = c.digits(2, "the second");
    if (c.accept('.') || c.accept(',')) fraction = c.fraction();  // ISO 8601 allows either mark
  }

  std::optional<int> offset_minutes;
  if (c.accept('Z') || c.accept('z')) {
    offset_minutes = 0;
  } else if (c.peek() == '+' || c.peek() == '-') {
    const int sign = c.peek() == '-' ? -1 : 1;
    c.accept(c.peek());
    const int zh = c.digits(2, "the zone's hours");
    int zm = 0;
    if (c.accept(':')) {
      zm = c.digits(2, "the zone's minutes");
    } else if (!c.done()) {
      zm = c.digits(2, "the zone's minutes");
    }
    check_range(text, zh, 0, 23, "zone hours");
    check_range(text, zm, 0, 59, "zone minutes");
    offset_minutes = sign * (zh * 60 + zm);
  }
  // RFC 9557's suffix: an IANA zone in brackets, alone or after an offset it must agree with.
  std::string_view zone_name;
  if (c.peek() == '[') {
    const std::size_t open = c.pos();
    const std::size_t close = text.find(']', open);
    if (close == std::string_view::npos) fail(text, "the zone name opened at position " + std::to_string(open + 1) + " has no ']'");
    zone_name = text.substr(open + 1, close - open - 1);
    if (zone_name.empty()) fail(text, "empty zone name in brackets");
    while (c.pos() <= close) c.accept(c.peek());
  }
  if (!offset_minutes && zone_name.empty()) {
    if (c.done()) fail(text, "the zone is missing (a local time without a zone is ambiguous)");
    fail(text, "unexpected character at position " + std::to_string(c.pos() + 1));
  }
  if (!c.done()) fail(text, "unexpected trailing text at position " + std::to_string(c.pos() + 1));

  check_range(text, month, 1, 12, "month");
  check_range(text, hour, 0, 23, "hour");
  check_range(text, minute, 0, 59, "minute");
  if (second == 60) {
    fail(text, "a leap second (:60) has no POSIX time; skypol's instants do not count leap seconds");
  }
  check_range(text, second, 0, 59, "second");
  const std::chrono::year_month_day ymd{std::chrono::year{year},
                                        std::chrono::month{static_cast<unsigned>(month)},
                                        std::chrono::day{static_cast<unsigned>(day)}};
  if (!ymd.ok()) {
    fail(text, "day " + std::to_string(day) + " does not exist in " + std::to_string(year) + "-" +
                   (month < 10 ? "0" : "") + std::to_string(month));
  }

  const long long local = days_from_civil(year, month, day) * 86400LL + hour * 3600LL + minute * 60LL + second;
  if (zone_name.empty()) return Instant{static_cast<double>(local - *offset_minutes * 60LL) + fraction};
  return Instant{static_cast<double>(in_zone(text, local, offset_minutes, zone_name)) + fraction};
}

CalendarUtc to_calendar(Instant t) {
  // ±1e12 s is ±31 700 years: far beyond any use, and keeps the integer conversions below exact.
  if (!(std::abs(t.unix_seconds) < 1e12)) {
    throw std::invalid_argument("instant " + std::to_string(t.unix_seconds) +
                                " s from 1970 is not finite or beyond ±1e12 s (±31 700 years)");
  }
  const double whole = std::floor(t.unix_seconds);
  const double fraction = t.unix_seconds - whole;
  const auto total = static_cast<long long>(whole);
  long long days = total / 86400;
  long long rem = total % 86400;
  if (rem < 0) {  // floor division for instants before 1970
    rem += 86400;
    --days;
  }
  const std::chrono::year_month_day ymd{std::chrono::sys_days{std::chrono::days{days}}};
  CalendarUtc cal{};
  cal.year = static_cast<int>(ymd.year());
  cal.month = static_cast<int>(static_cast<unsigned>(ymd.month()));
  cal.day = static_cast<int>(static_cast<unsigned>(ymd.day()));
  cal.hour = static_cast<int>(rem / 3600);
  cal.minute = static_cast<int>(rem % 3600 / 60);
  cal.second = static_cast<double>(rem % 60) + fraction;
  return cal;
}

std::string format_iso8601(Instant t) {
  if (!std::isfinite(t.unix_seconds)) throw std::invalid_argument("format_iso8601: the instant is not finite");
  // Round to the millisecond first so that 59.9996 s prints as the next minute, never as "60.000".
  const double ms_total = std::round(t.unix_seconds * 1000.0);
  const double whole_s = std::floor(ms_total / 1000.0);
  const int ms = static_cast<int>(ms_total - whole_s * 1000.0);
  const CalendarUtc c = to_calendar(Instant{whole_s});
  char buf[64];
  if (ms == 0) {
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02dZ", c.year, c.month, c.day, c.hour,
                  c.minute, static_cast<int>(c.second));
  } else {
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", c.year, c.month, c.day, c.hour,
                  c.minute, static_cast<int>(c.second), ms);
  }
  return buf;
}

}  // namespace skypol::sky
