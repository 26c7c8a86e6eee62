#include "render/scene.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "camera/orientation.h"
#include "camera/radial_lens.h"
#include "sky/rayleigh.h"

namespace skypol::render {
namespace {

sky::Instant instant_at(Fields& f, std::string_view key, const std::string& text) {
  try {
    return sky::parse_iso8601(text);
  } catch (const std::invalid_argument& e) {
    f.fail(key, e.what());
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

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(FileLoc{path, 0, 0}, "cannot open scene file");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

toml::table parse_toml(const std::string& text, const std::string& file_name) {
  try {
    return toml::parse(text, file_name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw SceneError(FileLoc{file_name, static_cast<int>(b.line), static_cast<int>(b.column)},
                     "TOML syntax: " + std::string(e.description()));
  }
}

}  // namespace

CameraSpec read_camera(Fields& c) {
  CameraSpec s;
  std::vector<std::string> models;
  for (auto m : {camera::Mapping::perspective, camera::Mapping::stereographic, camera::Mapping::equidistant,
                 camera::Mapping::equisolid, camera::Mapping::orthographic}) {
    models.emplace_back(camera::mapping_name(m));
  }
  s.model = c.choice("model", "equidistant", models);
  s.width = static_cast<int>(c.integer("width", 0, 1, 65536));
  s.height = static_cast<int>(c.integer("height", 0, 1, 65536));
  if (!c.has("width")) c.fail("width", "missing (image width in pixels)");
  if (!c.has("height")) c.fail("height", "missing (image height in pixels)");
  const std::optional<double> focal_mm = c.optional_number("focal_mm", 1e-3, 1e4);
  const std::optional<double> pitch_um = c.optional_number("pitch_um", 1e-2, 1e3);
  const std::optional<double> fx = c.optional_number("fx", 1e-3, 1e7);
  const std::optional<double> fy = c.optional_number("fy", 1e-3, 1e7);
  if (focal_mm && fx) c.fail("fx", "give either 'focal_mm' with 'pitch_um' or 'fx' (and 'fy'), not both");
  if (focal_mm) {
    if (!pitch_um) c.fail("pitch_um", "needed with 'focal_mm' (pixel pitch in micrometres)");
    s.fx = s.fy = *focal_mm * 1000.0 / *pitch_um;
  } else if (fx) {
    s.fx = *fx;
    s.fy = fy.value_or(*fx);
  } else {
    c.fail("focal_mm", "missing: give 'focal_mm' and 'pitch_um', or 'fx'");
  }
  s.cx = c.number("cx", (s.width - 1) / 2.0, -0.5, s.width - 0.5);
  s.cy = c.number("cy", (s.height - 1) / 2.0, -0.5, s.height - 0.5);
  s.fov_deg = c.number("fov_deg", 180, 1, 360);
  s.heading_deg = c.number("heading_deg", 0, -360, 360);
  s.tilt_deg = c.number("tilt_deg", 0, 0, 180);
  s.roll_deg = c.number("roll_deg", 0, -360, 360);
  const std::string transport = c.choice("transport", "meridional", {"meridional", "projected"});
  s.transport = transport == "projected" ? camera::Transport::projected : camera::Transport::meridional;
  c.finish();

  // The canonical description: every value explicit, so a stack rebuilds the exact camera.
  std::ostringstream os;
  os.precision(17);
  os << "model = \"" << s.model << "\"\nwidth = " << s.width << "\nheight = " << s.height << "\nfx = " << s.fx
     << "\nfy = " << s.fy << "\ncx = " << s.cx << "\ncy = " << s.cy << "\nfov_deg = " << s.fov_deg
     << "\nheading_deg = " << s.heading_deg << "\ntilt_deg = " << s.tilt_deg << "\nroll_deg = " << s.roll_deg
     << "\ntransport = \"" << transport << "\"\n";
  s.description = os.str();
  return s;
}

CameraSpec parse_camera(const std::string& toml_text, const std::string& file_name) {
  const toml::table t = parse_toml(toml_text, file_name);
  Fields f(t, file_name, "camera");
  return read_camera(f);
}

Scene parse_scene(const std::string& text, const std::string& file_name) {
  Scene scene;
  scene.file = file_name;
  scene.text = text;
  const toml::table root = parse_toml(text, file_name);
  Fields top(root, file_name, "");

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

  std::optional<Fields> cam = top.table("camera");
  if (!cam) top.fail("camera", "missing section [camera]");
  scene.camera = read_camera(*cam);

  if (std::optional<Fields> sky = top.table("sky")) {
    scene.sky.model = sky->choice("model", "rayleigh", {"rayleigh"});
    scene.sky.max_dolp = sky->number("max_dolp", 1.0, 0, 1);
    sky->finish();
  }

  if (std::optional<Fields> r = top.table("render")) {
    scene.render.spp = static_cast<int>(r->integer("spp", 1, 1, 4096));
    scene.render.seed = static_cast<std::uint64_t>(r->integer("seed", 0, 0, std::numeric_limits<long long>::max()));
    scene.render.bands = r->strings("bands", {"Y"});
    if (scene.render.bands.empty()) r->fail("bands", "needs at least one band name");
    r->finish();
  }

  std::string stem = file_name;
  if (auto slash = stem.find_last_of('/'); slash != std::string::npos) stem = stem.substr(slash + 1);
  if (auto dot = stem.rfind('.'); dot != std::string::npos) stem = stem.substr(0, dot);
  scene.output.path = "out/" + stem + ".exr";
  if (std::optional<Fields> o = top.table("output")) {
    scene.output.path = o->string("path", scene.output.path);
    scene.output.channels = o->strings("channels", scene.output.channels);
    for (const std::string& ch : scene.output.channels) {
      static const std::vector<std::string> legal{"S0", "S1", "S2", "S3", "DoLP", "AoLP", "mask"};
      if (std::find(legal.begin(), legal.end(), ch) == legal.end()) {
        o->fail("channels", "unknown channel '" + ch + "' (expected S0, S1, S2, S3, DoLP, AoLP, mask)");
      }
    }
    scene.output.half = o->choice("pixel_type", "float", {"float", "half"}) == "half";
    scene.output.compression = o->choice("compression", "zip", {"none", "zip", "zips", "piz", "rle", "pxr24", "b44", "dwaa"});
    o->finish();
  }
  top.finish();
  return scene;
}

Scene load_scene(const std::string& path) { return parse_scene(read_file(path), path); }

std::shared_ptr<const camera::Camera> build_camera(const CameraSpec& s) {
  camera::Intrinsics k;
  k.fx = s.fx;
  k.fy = s.fy;
  k.cx = s.cx;
  k.cy = s.cy;
  k.width = s.width;
  k.height = s.height;
  auto lens = std::make_shared<camera::RadialLens>(camera::parse_mapping(s.model), k,
                                                   s.fov_deg / 2 * std::numbers::pi / 180);
  return std::make_shared<camera::Camera>(
      lens, camera::world_from_heading_tilt_roll(s.heading_deg, s.tilt_deg, s.roll_deg), s.transport);
}

std::unique_ptr<sky::SkyModel> build_sky(const SkySpec& spec) {
  return std::make_unique<sky::RayleighSky>(sky::RayleighParams{spec.max_dolp});
}

}  // namespace skypol::render
