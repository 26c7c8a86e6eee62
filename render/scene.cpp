#include "render/scene.h"

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <limits>
#include <numbers>


namespace skypol::render {
namespace {

sky::Instant instant_at(Fields& f, std::string_view key, const std::string& text) {
  try {
    return sky::parse_iso8601(text);
  } catch (const std::invalid_argument& e) {
    f.fail(key, e.what());
  }
}

// The sky models are daylight skies: a scene whose every frame has the sun below the horizon is
// refused plainly (one night frame among day frames is fine: it renders the model's limit).
void require_daylight(const Scene& scene, const Fields& time) {
  double highest = -90;
  for (sky::Instant t : scene.times) {
    highest = std::max(highest, sky::sun_position(scene.site, t, scene.sun_options).elevation * 180 / std::numbers::pi);
  }
  if (highest < 0) {
    char msg[160];
    std::snprintf(msg, sizeof msg, "the sun is below the horizon in every frame (highest elevation %.1f deg): "
                  "nothing but night to render", highest);
    time.fail(time.has("instants") ? "instants" : "start", msg);
  }
}

std::vector<sky::Instant> read_times(Fields& t) {
  std::vector<sky::Instant> times;
  const std::vector<std::string> instants = t.strings("instants", {});
  const std::optional<std::string> start = t.optional_string("start");
  if (!instants.empty() && start) t.fail("start", "give either 'instants' or 'start'/'end'/'step_min', not both");
  for (const std::string& s : instants) times.push_back(instant_at(t, "instants", s));
  if (start) {
    const sky::Instant t0 = instant_at(t, "start", *start);
    const sky::Instant t1 = instant_at(t, "end", t.required_string("end"));
    const double step_s = 60.0 * t.required_number("step_min", 1e-3, 1e6);
    if (t1 < t0) t.fail("end", "must not be before 'start'");
    const auto n = static_cast<long long>(std::floor((t1.unix_seconds - t0.unix_seconds) / step_s + 1e-9));
    if (n > 100000) t.fail("step_min", "gives more than 100000 frames");
    for (long long i = 0; i <= n; ++i) {
      times.push_back(sky::Instant{t0.unix_seconds + static_cast<double>(i) * step_s});
    }
  }
  if (times.empty()) t.fail("instants", "no times: give 'instants' or 'start'/'end'/'step_min'");
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (!(times[i - 1] < times[i])) t.fail("instants", "times must be strictly increasing");
  }
  return times;
}

}  // namespace

Scene scene_from_source(const SceneSource& source) {
  const std::string& file_name = source.file;
  Scene scene;
  scene.file = file_name;
  scene.text = source.text;
  Fields top(source.root, file_name, "");

  std::optional<Fields> site = top.table("site");
  if (!site) top.fail("site", "missing section [site] (latitude_deg, longitude_deg)");
  scene.site.latitude_deg = site->required_number("latitude_deg", -90, 90);
  scene.site.longitude_deg = site->required_number("longitude_deg", -180, 360);
  scene.site.height_m = site->number("height_m", 0, -1000, 1e5);
  site->finish();

  if (std::optional<Fields> atm = top.table("atmosphere")) {
    scene.sun_options.pressure_hpa = atm->number("pressure_hpa", 0, 0, 1200);
    scene.sun_options.temperature_c = atm->number("temperature_c", 15, -90, 60);
    scene.sun_options.relative_humidity = atm->number("relative_humidity", 0.5, 0, 1);
    scene.sun_options.ut1_minus_utc_s = atm->number("ut1_minus_utc_s", 0, -0.9, 0.9);
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

  if (std::optional<Fields> sky = top.table("sky")) scene.sky = read_sky(*sky);
  if (std::optional<Fields> occ = top.table("occluders")) scene.occluders = read_occluders(*occ);

  if (std::optional<Fields> r = top.table("render")) {
    scene.render.spp = static_cast<int>(r->integer("spp", 1, 1, 4096));
    scene.render.seed = static_cast<std::uint64_t>(r->integer("seed", 0, 0, std::numeric_limits<long long>::max()));
    scene.render.bands = r->strings("bands", {"Y"});
    if (scene.render.bands.empty()) r->fail("bands", "needs at least one band name");
    r->finish();
  }

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
  scene.output.path = "out/" + stem + ".exr";
  if (std::optional<Fields> o = top.table("output")) {
    scene.output.path = o->string("path", scene.output.path);
    scene.output.channels = o->strings("channels", scene.output.channels);
    for (const std::string& ch : scene.output.channels) {
      static const std::vector<std::string> legal{"S0", "S1", "S2", "S3", "DoLP", "AoLP", "mask", "raw"};
      if (std::find(legal.begin(), legal.end(), ch) == legal.end()) {
        o->fail("channels", "unknown channel '" + ch + "' (expected S0, S1, S2, S3, DoLP, AoLP, mask, raw)");
      }
      if (ch == "raw" && !scene.sensor) o->fail("channels", "'raw' is the sensor's mosaic: it needs a [sensor] section");
    }
    scene.output.half = o->choice("pixel_type", "float", {"float", "half"}) == "half";
    scene.output.compression = o->choice("compression", "zip", {"none", "zip", "zips", "piz", "rle", "pxr24", "b44", "dwaa"});
    o->finish();
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

}  // namespace skypol::render
