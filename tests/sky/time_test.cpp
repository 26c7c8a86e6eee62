// ISO 8601 parsing and printing. Expected POSIX seconds come from GNU date (`date -u -d … +%s`),
// not from skypol.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

#include "sky/time.h"

using skypol::sky::CalendarUtc;
using skypol::sky::format_iso8601;
using skypol::sky::Instant;
using skypol::sky::parse_iso8601;
using skypol::sky::to_calendar;

TEST_CASE("UTC instants parse to the POSIX seconds GNU date gives", "[time]") {
  CHECK(parse_iso8601("1970-01-01T00:00:00Z").unix_seconds == 0.0);
  CHECK(parse_iso8601("2000-01-01T00:00:00Z").unix_seconds == 946684800.0);
  CHECK(parse_iso8601("2022-09-23T10:30:00Z").unix_seconds == 1663929000.0);
  CHECK(parse_iso8601("1969-12-31T23:59:59Z").unix_seconds == -1.0);
  CHECK(parse_iso8601("2003-10-17T19:30:30Z").unix_seconds == 1066419030.0);
}

TEST_CASE("every accepted zone form means the same instant", "[time]") {
  const double utc = 1663929000.0;  // 2022-09-23T10:30:00Z
  for (const char* text : {"2022-09-23T12:30:00+02:00", "2022-09-23T12:30:00+0200", "2022-09-23T12:30:00+02",
                           "2022-09-23T03:30:00-07:00", "2022-09-23T03:30:00-0700", "2022-09-23T03:30:00-07",
                           "2022-09-23T16:00:00+05:30", "2022-09-23T16:15:00+0545", "2022-09-23T10:30:00-00:00",
                           "2022-09-23 10:30:00Z", "2022-09-23t10:30:00z", "2022-09-23T10:30Z"}) {
    INFO(text);
    CHECK(parse_iso8601(text).unix_seconds == utc);
  }
}

TEST_CASE("fractional seconds with a point or a comma", "[time]") {
  CHECK(parse_iso8601("2022-09-23T10:30:00.5Z").unix_seconds == 1663929000.5);
  CHECK(parse_iso8601("2022-09-23T10:30:00,25Z").unix_seconds == 1663929000.25);
  CHECK(parse_iso8601("2022-09-23 10:30:00.5-07:00").unix_seconds == 1663929000.5 + 7 * 3600);
  CHECK(parse_iso8601("2022-09-23T10:30:00.123456Z").unix_seconds == Approx(1663929000.123456).margin(1e-6));
}

TEST_CASE("leap days follow the Gregorian rules, also across a zone", "[time]") {
  CHECK(parse_iso8601("2024-02-29T12:00:00Z").unix_seconds == 1709208000.0);
  CHECK(parse_iso8601("2024-03-01T00:30:00+01:00").unix_seconds == 1709249400.0);  // = 2024-02-29T23:30Z
  CHECK(format_iso8601(parse_iso8601("2024-03-01T00:30:00+01:00")) == "2024-02-29T23:30:00Z");
  CHECK_NOTHROW(parse_iso8601("2000-02-29T00:00:00Z"));                           // divisible by 400
  CHECK_THROWS_AS(parse_iso8601("1900-02-29T00:00:00Z"), std::invalid_argument);  // by 100, not 400
  CHECK_THROWS_AS(parse_iso8601("2023-02-29T00:00:00Z"), std::invalid_argument);
  const CalendarUtc c = to_calendar(Instant{1709208000.0});
  CHECK(c.year == 2024);
  CHECK(c.month == 2);
  CHECK(c.day == 29);
  CHECK(c.hour == 12);
}

TEST_CASE("format then parse is the identity to the millisecond", "[time]") {
  for (double t : {0.0, -1.0, 946684800.0, 1663929000.5, 1709249400.125, -86400.0 * 365.25 * 30 + 0.001,
                   4102444799.999}) {
    INFO(t);
    CHECK(parse_iso8601(format_iso8601(Instant{t})).unix_seconds == Approx(t).margin(1e-6));
  }
  CHECK(format_iso8601(Instant{1663929000.0}) == "2022-09-23T10:30:00Z");
  CHECK(format_iso8601(Instant{1663929000.5}) == "2022-09-23T10:30:00.500Z");
  CHECK(format_iso8601(Instant{-1.0}) == "1969-12-31T23:59:59Z");
  // Rounded to the millisecond before splitting into fields: never "…:59.1000" or ":60".
  CHECK(format_iso8601(Instant{1663929059.9996}) == "2022-09-23T10:31:00Z");
  CHECK(to_calendar(Instant{-0.25}).second == Approx(59.75));
  CHECK_THROWS_AS(to_calendar(Instant{1e300}), std::invalid_argument);  // no overflow in the conversions
  CHECK_THROWS_AS(format_iso8601(Instant{std::nan("")}), std::invalid_argument);
}

TEST_CASE("bad instants throw std::invalid_argument saying what was expected", "[time][bad-input]") {
  for (const char* text :
       {"", "2022-09-23", "2022-09-23T10:30:00", "2022-09-23T10:30:00 ", "2022-13-01T00:00:00Z",
        "2022-00-10T00:00:00Z", "2022-09-31T00:00:00Z", "2022-09-23T24:00:00Z", "2022-09-23T10:60:00Z",
        "2022-09-23T10:30:60Z", "2022-09-23T10:30:00+25:00", "2022-09-23T10:30:00+02:60",
        "2022-09-23T10:30:00Zjunk", "2022-9-23T10:30:00Z", "2022-09-23T10:30:00.Z", "2022-09-23X10:30:00Z",
        "2022-09-23T10:30:00+2", "2022-09-23T10:30:00+02:0", "yesterday", "2022-09-23T10:30:00 UTC"}) {
    INFO(text);
    try {
      parse_iso8601(text);
      FAIL("accepted a bad instant");
    } catch (const std::invalid_argument& e) {
      const std::string msg = e.what();
      CHECK(msg.find("invalid ISO 8601 instant") != std::string::npos);
      CHECK(msg.find("expected") != std::string::npos);
      CHECK(msg.find(std::string("\"") + text + "\"") != std::string::npos);
    }
  }
  // The specific problem is named.
  CHECK_THROWS_WITH(parse_iso8601("2022-09-23T10:30:00"), Catch::Contains("zone is missing"));
  CHECK_THROWS_WITH(parse_iso8601("2023-02-29T00:00:00Z"), Catch::Contains("does not exist"));
  CHECK_THROWS_WITH(parse_iso8601("2022-09-23T10:30:60Z"), Catch::Contains("leap second"));
}

TEST_CASE("IANA zones in brackets (RFC 9557) follow the tz database, daylight saving included", "[time]") {
  // Expected offsets from the zones' published rules, not from the code under test: Paris is
  // +02:00 in September and +01:00 in December 2022; Sydney +11:00 in January (AEDT).
  CHECK(parse_iso8601("2022-09-23T12:30:00[Europe/Paris]") == parse_iso8601("2022-09-23T10:30:00Z"));
  CHECK(parse_iso8601("2022-12-21T12:00:00[Europe/Paris]") == parse_iso8601("2022-12-21T11:00:00Z"));
  CHECK(parse_iso8601("2022-01-15T12:00:00[Australia/Sydney]") == parse_iso8601("2022-01-15T01:00:00Z"));
  // An offset with the zone must agree with it; it also picks one of a repeated hour.
  CHECK(parse_iso8601("2022-09-23T12:30:00+02:00[Europe/Paris]") == parse_iso8601("2022-09-23T10:30:00Z"));
  CHECK(parse_iso8601("2022-10-30T02:30:00+02:00[Europe/Paris]") == parse_iso8601("2022-10-30T00:30:00Z"));
  CHECK(parse_iso8601("2022-10-30T02:30:00+01:00[Europe/Paris]") == parse_iso8601("2022-10-30T01:30:00Z"));
  CHECK_THROWS_WITH(parse_iso8601("2022-09-23T12:30:00+01:00[Europe/Paris]"), Catch::Contains("disagrees"));
  // Clocks forward on 27 March 2022 at 02:00 (02:30 never happens); back on 30 October (02:30 twice).
  CHECK_THROWS_WITH(parse_iso8601("2022-03-27T02:30:00[Europe/Paris]"), Catch::Contains("does not exist"));
  CHECK_THROWS_WITH(parse_iso8601("2022-10-30T02:30:00[Europe/Paris]"), Catch::Contains("occurs twice"));
  CHECK_THROWS_WITH(parse_iso8601("2022-09-23T12:30:00[Mars/Olympus_Mons]"), Catch::Contains("unknown time zone"));
  CHECK_THROWS_WITH(parse_iso8601("2022-09-23T12:30:00[Europe/Paris"), Catch::Contains("no ']'"));
}
