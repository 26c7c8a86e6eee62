#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>

#include "scene/output_defaults.h"
#include "sky/units.h"

namespace skypol::scene {
namespace {

std::string two(int v) { return (v < 10 ? "0" : "") + std::to_string(v); }

std::string date_text(const toml::date& d) {
  return std::to_string(d.year) + "-" + two(d.month) + "-" + two(d.day);
}

std::string time_text(const toml::time& t) {
  std::string s = two(t.hour) + ":" + two(t.minute) + ":" + two(t.second);
  if (t.nanosecond) {
    const std::string ns = std::to_string(t.nanosecond);
    s += "." + std::string(9 - ns.size(), '0') + ns;
  }
  return s;
}

// A TOML value that stands for an instant, a date or a time of day, as the text sky::parse_iso8601
// and the composition below read: strings as written, TOML's own date/time values converted.
// `what` says what was expected, for the error.
std::string temporal_text(const Fields& f, std::string_view key, const toml::node& n, const char* what) {
  if (const auto* s = n.as_string()) return s->get();
  if (const auto* dt = n.as_date_time()) {
    const toml::date_time& v = dt->get();
    if (!v.offset) f.fail(key, "a date and time needs a zone (Z or +hh:mm), e.g. 2022-09-23T08:00:00+02:00");
    const int off = v.offset->minutes;
    const std::string zone = off == 0 ? "Z" : (off < 0 ? "-" : "+") + two(std::abs(off) / 60) + ":" + two(std::abs(off) % 60);
    return date_text(v.date) + "T" + time_text(v.time) + zone;
  }
  if (const auto* d = n.as_date()) return date_text(d->get());
  if (const auto* t = n.as_time()) return time_text(t->get());
  f.fail(key, std::string("expected ") + what);
}

// One value or an array of them, each as text.
std::vector<std::string> temporal_list(Fields& f, std::string_view key, const char* what) {
  std::vector<std::string> out;
  const toml::node* n = f.node(key);
  if (!n) return out;
  if (const toml::array* a = n->as_array()) {
    for (const toml::node& e : *a) out.push_back(temporal_text(f, key, e, what));
  } else {
    out.push_back(temporal_text(f, key, *n, what));
  }
  return out;
}

std::optional<std::string> temporal(Fields& f, std::string_view key, const char* what) {
  const toml::node* n = f.node(key);
  if (!n) return std::nullopt;
  return temporal_text(f, key, *n, what);
}

sky::Instant instant_at(const Fields& f, std::string_view key, const std::string& text) {
  try {
    return sky::parse_iso8601(text);
  } catch (const std::invalid_argument& e) {
    f.fail(key, e.what());
  }
}

// The sky models are daylight skies: a scene whose every frame has the sun below the horizon is
// refused plainly (one night frame among day frames is fine: it renders the model's limit).
void require_daylight(const Scene& scene, const Fields& time) {
  // Stops at the first day frame: a sun position costs ~60 µs (IAU 2000A nutation), and a sweep
  // loads every variant's scene.
  double highest = -90;
  for (sky::Instant t : scene.times) {
    highest = std::max(highest, deg_from_rad(sky::sun_position(scene.site, t, scene.sun_options).elevation));
    if (highest >= 0) break;
  }
  if (highest < 0) {
    char msg[160];
    std::snprintf(msg, sizeof msg, "the sun is below the horizon in every frame (highest elevation %.1f deg): "
                  "nothing but night to render", highest);
    time.fail(time.has("instants") ? "instants" : time.has("dates") ? "dates" : "start", msg);
  }
}

constexpr long long kMaxFrames = 100000;

// Frames from t0 every step_s up to and including t1.
void append_range(Fields& t, sky::Instant t0, sky::Instant t1, double step_s, std::string_view end_key,
                  std::vector<sky::Instant>& times) {
  if (t1 < t0) t.fail(end_key, "must not be before the start");
  const auto n = static_cast<long long>(std::floor((t1.unix_seconds - t0.unix_seconds) / step_s + 1e-9));
  if (n + static_cast<long long>(times.size()) >= kMaxFrames) t.fail("step_min", "gives more than 100000 frames");
  for (long long i = 0; i <= n; ++i) times.push_back(sky::Instant{t0.unix_seconds + static_cast<double>(i) * step_s});
}

// The third form: calendar dates × times of day in one zone, so that a sweep can vary the date
// alone ("time.dates" = ...).
void read_dates(Fields& t, const std::vector<std::string>& dates, std::vector<sky::Instant>& times) {
  const std::string zone_text = t.required_string("zone");
  if (zone_text.empty()) t.fail("zone", "expected Z, an offset such as +02:00, or an IANA zone such as Europe/Paris");
  // An offset follows the time as written; an IANA name goes in brackets (RFC 9557), so that each
  // date gets the zone's own offset that day, daylight saving included.
  const bool is_offset = zone_text == "Z" || zone_text.front() == '+' || zone_text.front() == '-';
  const std::string zone = is_offset ? zone_text : "[" + zone_text + "]";
  try {
    (void)sky::parse_iso8601("2000-01-01T12:00" + zone);
  } catch (const std::invalid_argument&) {
    if (is_offset) t.fail("zone", "'" + zone_text + "' is not a zone: expected Z or an offset such as +02:00 or -03:30");
    t.fail("zone", "'" + zone_text + "' is not a zone: expected Z, an offset such as +02:00, or an IANA zone "
                   "such as Europe/Paris from the system's tz database");
  }
  const std::vector<std::string> of_day = temporal_list(t, "times_of_day", "a time of day such as \"08:30\"");
  const std::optional<std::string> day_start = temporal(t, "day_start", "a time of day such as \"06:00\"");
  if (!of_day.empty() && day_start) t.fail("day_start", "give either 'times_of_day' or 'day_start'/'day_end'/'step_min', not both");
  if (of_day.empty() && !day_start) t.fail("dates", "dates need 'times_of_day' or 'day_start'/'day_end'/'step_min'");
  for (const std::string& date : dates) {
    if (date.find('T') != std::string::npos || date.size() != 10) {
      t.fail("dates", "'" + date + "' is not a calendar date: expected YYYY-MM-DD");
    }
    (void)instant_at(t, "dates", date + "T12:00" + zone);  // noon: a date whose midnight a zone skips is still a date
    if (day_start) {
      const sky::Instant t0 = instant_at(t, "day_start", date + "T" + *day_start + zone);
      const std::optional<std::string> day_end = temporal(t, "day_end", "a time of day such as \"17:00\"");
      if (!day_end) t.fail("day_end", "missing (the last time of day, e.g. \"17:00\")");
      const sky::Instant t1 = instant_at(t, "day_end", date + "T" + *day_end + zone);
      append_range(t, t0, t1, 60.0 * t.required_number("step_min", 1e-3, 1e6), "day_end", times);
    } else {
      for (const std::string& tod : of_day) times.push_back(instant_at(t, "times_of_day", date + "T" + tod + zone));
      if (static_cast<long long>(times.size()) > kMaxFrames) t.fail("dates", "gives more than 100000 frames");
    }
  }
}

std::vector<sky::Instant> read_times(Fields& t) {
  std::vector<sky::Instant> times;
  const char* instant = "an ISO 8601 date and time with a zone, e.g. \"2022-09-23T08:00:00+02:00\"";
  const std::vector<std::string> instants = temporal_list(t, "instants", instant);
  const std::optional<std::string> start = temporal(t, "start", instant);
  const std::vector<std::string> dates = temporal_list(t, "dates", "a date such as \"2022-09-23\"");
  const int forms = int(!instants.empty()) + int(start.has_value()) + int(!dates.empty());
  if (forms > 1) {
    t.fail(!dates.empty() ? "dates" : "start", "give one of 'instants', 'start'/'end'/'step_min' or 'dates' with times of day");
  }
  for (const std::string& s : instants) times.push_back(instant_at(t, "instants", s));
  if (start) {
    const sky::Instant t0 = instant_at(t, "start", *start);
    const std::optional<std::string> end = temporal(t, "end", instant);
    if (!end) t.fail("end", "missing (the last instant, e.g. \"2022-09-23T17:00:00Z\")");
    const sky::Instant t1 = instant_at(t, "end", *end);
    append_range(t, t0, t1, 60.0 * t.required_number("step_min", 1e-3, 1e6), "end", times);
  }
  if (!dates.empty()) read_dates(t, dates, times);
  if (times.empty()) t.fail("instants", "no times: give 'instants', 'start'/'end'/'step_min', or 'dates' and times of day");
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (!(times[i - 1] < times[i])) {
      t.fail(!dates.empty() ? "dates" : "instants", "times must be strictly increasing (" +
                                                         sky::format_iso8601(times[i - 1]) + " then " +
                                                         sky::format_iso8601(times[i]) + ")");
    }
  }
  return times;
}

}  // namespace

sky::Site read_site(Fields& site_table) {
  sky::Site site;
  site.latitude_deg = site_table.required_number("latitude_deg", -90, 90);
  site.longitude_deg = site_table.required_number("longitude_deg", -180, 360);
  site.height_m = site_table.number("height_m", 0, -1000, 1e5);
  site_table.finish();
  return site;
}

Scene scene_from_source(const SceneSource& source) {
  const std::string& file_name = source.file;
  Scene scene;
  scene.file = file_name;
  scene.text = source.text;
  scene.notes = source.notes;
  Fields top(source.root, file_name, "");

  std::optional<Fields> site = top.table("site");
  if (!site) top.fail("site", "missing section [site] (latitude_deg, longitude_deg)");
  scene.site = read_site(*site);

  if (std::optional<Fields> atm = top.table("atmosphere")) {
    scene.sun_options.pressure_hpa = atm->number("pressure_hpa", 0, 0, 1200);
    scene.sun_options.temperature_c = atm->number("temperature_c", 15, -90, 60);
    scene.sun_options.relative_humidity = atm->number("relative_humidity", 0.5, 0, 1);
    scene.sun_options.ut1_minus_utc_s = atm->number("ut1_minus_utc_s", 0, -0.9, 0.9);
    scene.sun_options.refraction = sky::parse_refraction(
        atm->choice("refraction", std::string(sky::refraction_name(sky::Refraction::spa)), {"spa", "erfa"}));
    scene.sun_options.delta_t_s = atm->optional_number("delta_t_s", -8000, 8000);
    atm->finish();
  }

  std::optional<Fields> time = top.table("time");
  if (!time) top.fail("time", "missing section [time] (instants, or start/end/step_min)");
  scene.times = read_times(*time);
  time->finish();
  require_daylight(scene, *time);

  std::optional<Fields> cam = top.table("camera");
  if (!cam) top.fail("camera", "missing section [camera]");
  scene.camera = read_camera(*cam);

  std::optional<Fields> sky_table = top.table("sky");
  if (sky_table) scene.sky = read_sky(*sky_table);
  if (std::optional<Fields> occ = top.table("occluders")) scene.occluders = read_occluders(*occ);

  if (std::optional<Fields> r = top.table("render")) {
    scene.render.spp = static_cast<int>(r->integer("spp", 1, 1, 4096));
    scene.render.seed = static_cast<std::uint64_t>(r->integer("seed", 0, 0, std::numeric_limits<long long>::max()));
    scene.render.bands = r->strings("bands", {"Y"});
    if (scene.render.bands.empty()) r->fail("bands", "needs at least one band name");
    r->finish();
  }
  if (sky_table) check_sky_for_scene(*sky_table, scene);

  if (std::optional<Fields> sensor = top.table("sensor")) {
    scene.sensor = read_sensor(*sensor, scene.camera);
    const bool colour = scene.sensor->dofp.color_filter != camera::ColorFilter::none;
    if (colour && scene.render.bands != std::vector<std::string>{"R", "G", "B"}) {
      sensor->fail("color_filter", "a colour sensor records bands R, G, B: set [render] bands = [\"R\", \"G\", \"B\"]");
    }
    if (!colour && scene.render.bands.size() != 1) {
      sensor->fail("color_filter", "a mono sensor records one band; [render] bands names " +
                                       std::to_string(scene.render.bands.size()));
    }
  }

  std::string stem = file_name;
  if (auto slash = stem.find_last_of('/'); slash != std::string::npos) stem = stem.substr(slash + 1);
  if (auto dot = stem.rfind('.'); dot != std::string::npos) stem = stem.substr(0, dot);
  if (std::optional<Fields> o = top.table("output")) {
    scene.output = read_output(*o, stem, scene.sensor.has_value());
  } else {
    scene.output.path = "out/" + stem + ".exr";
  }
  top.finish();
  return scene;
}

Scene parse_scene(const std::string& text, const std::string& file_name) {
  return scene_from_source(parse_scene_source(text, file_name));
}

Scene load_scene(const std::string& path, const std::vector<Override>& overrides) {
  return scene_from_source(load_scene_source(path, overrides));
}

}  // namespace skypol::scene
