// Instants in UTC, parsed from and printed as ISO 8601. Everything time-dependent in skypol takes an
// Instant; zones exist only at the text boundary.
#pragma once

#include <string>
#include <string_view>

namespace skypol::sky {

// A UTC instant as seconds since 1970-01-01T00:00:00Z, POSIX-style (leap seconds are not counted,
// exactly as in ISO 8601 UTC calendar text). double resolves ~0.3 µs today, far below any use here.
struct Instant {
  double unix_seconds = 0;
  friend auto operator<=>(const Instant&, const Instant&) = default;
};

// Parses "2022-09-23T10:30:00Z", "2022-09-23T12:30:00+02:00", "2022-09-23 10:30:00.5-07:00",
// a date and time with an explicit zone (Z or ±hh:mm / ±hhmm / ±hh), or with an IANA zone in
// brackets as RFC 9557 writes it: "2022-09-23T12:30:00[Europe/Paris]" (the offset then comes from
// the system's tz database, daylight saving included; a skipped local time is an error, a repeated
// one needs the offset too: "2022-10-30T02:30:00+01:00[Europe/Paris]"). Also accepted: seconds
// omitted ("…T10:30Z"), any number of fractional digits after '.' or ',', lower-case 't'/'z'.
// A missing zone, an invalid field (month 13, 30 February, hour 24, a leap second :60 — POSIX
// time cannot hold it) or trailing text throws std::invalid_argument quoting the text, naming
// the problem and its position, and showing the expected form.
Instant parse_iso8601(std::string_view text);

// "2022-09-23T10:30:00Z" (fractional seconds printed only when non-zero, to the millisecond).
std::string format_iso8601(Instant t);

// Calendar fields of an instant in UTC (for ERFA and for headers).
struct CalendarUtc {
  int year, month, day, hour, minute;
  double second;
};
CalendarUtc to_calendar(Instant t);

}  // namespace skypol::sky
