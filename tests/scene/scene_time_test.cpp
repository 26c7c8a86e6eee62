// The [time] section: instants, ranges, and dates × times of day, with zones; TOML's own date and
// time values; and every way of getting it wrong, reported at its key.
#include <catch2/catch.hpp>

#include "scene/scene.h"

using skypol::scene::parse_scene;
using skypol::scene::SceneError;

namespace {

const char* kRest = R"(
[site]
latitude_deg = 31.846944
longitude_deg = 117.295278

[camera]
model = "equidistant"
fx = 20
width = 64
height = 64
)";

std::vector<double> seconds(const std::string& time_section) {
  std::vector<double> out;
  for (const auto& t : parse_scene(time_section + kRest, "t.toml").times) out.push_back(t.unix_seconds);
  return out;
}

std::string error_of(const std::string& time_section) {
  try {
    parse_scene(time_section + kRest, "t.toml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

constexpr double k20180326 = 1522022400.0;  // 2018-03-26T00:00:00Z (date -u -d 2018-03-26 +%s)

}  // namespace

TEST_CASE("dates x times of day in a zone give the local times in UTC", "[scene][time]") {
  // Sun et al. 2019, Table 1: six local times in Hefei, UTC+8.
  const auto s = seconds(R"([time]
dates = "2018-03-26"
zone = "+08:00"
times_of_day = ["08:30", "10:00", "11:05", "14:28", "15:38", "17:00"]
)");
  REQUIRE(s.size() == 6);
  CHECK(s[0] == k20180326 + 0.5 * 3600);            // 08:30+08:00 = 00:30Z
  CHECK(s[2] == k20180326 + 3 * 3600 + 5 * 60);     // 11:05+08:00 = 03:05Z
  CHECK(s[5] == k20180326 + 9 * 3600);              // 17:00+08:00 = 09:00Z
}

TEST_CASE("a named IANA zone gives each date its own offset, daylight saving included", "[scene][time]") {
  // Paris: CET (+01:00) until the last Sunday of March 2018 (the 25th) at 01:00Z, CEST (+02:00)
  // after; the EU rule, independent of skypol. Noon local on the 24th and the 26th.
  const auto s = seconds(R"([time]
dates = ["2018-03-24", "2018-03-26"]
zone = "Europe/Paris"
times_of_day = ["12:00"]
)");
  REQUIRE(s.size() == 2);
  CHECK(s[0] == k20180326 - 2 * 86400 + 11 * 3600);  // 12:00+01:00 = 11:00Z
  CHECK(s[1] == k20180326 + 10 * 3600);              // 12:00+02:00 = 10:00Z
}

TEST_CASE("several dates, each with a day range", "[scene][time]") {
  const auto s = seconds(R"([time]
dates = ["2018-03-26", 2018-03-28]
zone = "-03:30"
day_start = "06:00"
day_end = 07:00:00
step_min = 30
)");
  REQUIRE(s.size() == 6);
  CHECK(s[0] == k20180326 + 9.5 * 3600);             // 06:00-03:30 = 09:30Z
  CHECK(s[2] == k20180326 + 10.5 * 3600);
  CHECK(s[3] == k20180326 + 2 * 86400 + 9.5 * 3600);  // the second date
}

TEST_CASE("instants and ranges accept TOML offset date-times as well as strings", "[scene][time]") {
  const auto a = seconds("[time]\ninstants = [2018-03-26T08:00:00+08:00, \"2018-03-26T01:00:00Z\"]\n");
  CHECK(a == std::vector<double>{k20180326, k20180326 + 3600});
  const auto b = seconds("[time]\nstart = 2018-03-26T00:00:00Z\nend = \"2018-03-26T01:00:00Z\"\nstep_min = 20\n");
  CHECK(b == std::vector<double>{k20180326, k20180326 + 1200, k20180326 + 2400, k20180326 + 3600});
  const auto c = seconds("[time]\ninstants = 2018-03-26T00:00:00.25Z\n");  // one instant, fractions kept
  CHECK(c == std::vector<double>{k20180326 + 0.25});
}

TEST_CASE("a time without a zone is an error, never a guess", "[scene][time][errors]") {
  CHECK_THAT(error_of("[time]\ninstants = [2018-03-26T08:00:00]\n"),
             Catch::StartsWith("t.toml:2:12: error: key 'time.instants': a date and time needs a zone"));
  CHECK_THAT(error_of("[time]\ndates = \"2018-03-26\"\ntimes_of_day = [\"08:00\"]\n"),
             Catch::Contains("missing key 'time.zone'"));
  CHECK_THAT(error_of("[time]\ndates = \"2018-03-26\"\nzone = \"Mars/Olympus_Mons\"\ntimes_of_day = [\"08:00\"]\n"),
             Catch::StartsWith("t.toml:3:8: error: key 'time.zone': 'Mars/Olympus_Mons' is not a zone"));
  // A local time that daylight saving skips is refused at its key (Paris, 27 March 2022, 02:00 → 03:00).
  CHECK_THAT(error_of("[time]\ndates = \"2022-03-27\"\nzone = \"Europe/Paris\"\ntimes_of_day = [\"02:30\"]\n"),
             Catch::StartsWith("t.toml:4:16: error: key 'time.times_of_day':") && Catch::Contains("does not exist in Europe/Paris"));
}

TEST_CASE("[time] errors name the key", "[scene][time][errors]") {
  CHECK_THAT(error_of("[time]\ndates = \"2018-03-26\"\nzone = \"Z\"\n"), Catch::Contains("need 'times_of_day'"));
  CHECK_THAT(error_of("[time]\ndates = \"2018-02-30\"\nzone = \"Z\"\ntimes_of_day = [\"08:00\"]\n"),
             Catch::StartsWith("t.toml:2:9: error: key 'time.dates':"));
  CHECK_THAT(error_of("[time]\ndates = \"2018-03-26T08:00\"\nzone = \"Z\"\ntimes_of_day = [\"08:00\"]\n"),
             Catch::Contains("is not a calendar date"));
  CHECK_THAT(error_of("[time]\ndates = \"2018-03-26\"\nzone = \"Z\"\ntimes_of_day = [\"25:00\"]\n"),
             Catch::StartsWith("t.toml:4:16: error: key 'time.times_of_day':"));
  CHECK_THAT(error_of("[time]\ndates = \"2018-03-26\"\nzone = \"Z\"\ntimes_of_day = [\"10:00\", \"09:00\"]\n"),
             Catch::Contains("strictly increasing (2018-03-26T10:00:00Z then 2018-03-26T09:00:00Z)"));
  CHECK_THAT(error_of("[time]\ndates = \"2018-03-26\"\nzone = \"Z\"\ntimes_of_day = [\"08:00\"]\nday_start = \"06:00\"\n"),
             Catch::Contains("give either 'times_of_day' or 'day_start'"));
  CHECK_THAT(error_of("[time]\ninstants = [\"2018-03-26T08:00Z\"]\ndates = \"2018-03-26\"\n"),
             Catch::Contains("give one of 'instants', 'start'/'end'/'step_min' or 'dates'"));
  CHECK_THAT(error_of("[time]\ninstants = [\"2018-03-26T08:00Z\"]\nzone = \"Z\"\n"),
             Catch::Contains("unknown key 'time.zone'"));  // zone belongs to the dates form only
  CHECK_THAT(error_of("[time]\ninstants = [3]\n"), Catch::Contains("key 'time.instants': expected an ISO 8601"));
  CHECK_THAT(error_of("[time]\nstart = \"2018-03-26T08:00Z\"\nstep_min = 5\n"), Catch::Contains("key 'time.end': missing"));
  CHECK_THAT(error_of("[time]\nstart = \"2018-03-26T08:00Z\"\nend = \"2019-03-26T08:00Z\"\nstep_min = 1\n"),
             Catch::Contains("more than 100000 frames"));
}
