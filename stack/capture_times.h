// When each captured frame was taken, from what cameras and pipelines leave behind: a time in the
// file name (a small strptime-like format), the EXIF/TIFF DateTimeOriginal tag, or a CSV of
// (file, time). Names and EXIF carry no zone: `zone` supplies it as parse_iso8601 accepts it
// ("Z", "+02:00", or "[Europe/Paris]" for the tz database's rules, daylight saving included).
#pragma once

#include <map>
#include <string>

#include "sky/time.h"

namespace skypol::stack {

// `format` is matched against the whole file name: %Y (4 digits), %m %d %H %M %S (2 digits; %S
// may be followed by a fraction ".ddd"), `*` (any run of characters, the shortest that lets the
// rest match), %% (a '%'), anything else literally. E.g. "*_%Y%m%dT%H%M%S*" finds
// 20220923T103000 in "sky_003_20220923T103000Z.png". Throws std::invalid_argument saying what
// did not match.
sky::Instant time_from_name(const std::string& file_name, const std::string& format, const std::string& zone);

// "2022:09:23 10:30:00" or "2022:09:23 10:30:00.250" (EXIF's form, read_raw_frame's exif_time).
sky::Instant time_from_exif(const std::string& exif, const std::string& zone);

// Lines "file,time" (a first line "file,time" is a header and skipped; blank lines and lines
// starting with '#' too). The time is ISO 8601 (sky/time.h), with its own zone or else `zone`.
// Keys are the file names as written. Throws SceneError at the CSV's file and line.
std::map<std::string, sky::Instant> read_times_csv(const std::string& path, const std::string& zone);

}  // namespace skypol::stack
