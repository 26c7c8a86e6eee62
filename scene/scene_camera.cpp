// The [camera] section: lens (any camera::make_lens model, or a preset lens on a preset sensor),
// orientation (heading/tilt/roll or a quaternion) and polarization transport.
#include <cmath>
#include <filesystem>
#include <numbers>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "camera/lens_registry.h"
#include "camera/orientation.h"
#include "camera/presets.h"
#include "scene/scene.h"
#include "sky/units.h"

namespace skypol::scene {
namespace {

// The [camera] keys that a camera::make_lens message may name, in the order they are searched.
const std::vector<std::string>& lens_keys() {
  static const std::vector<std::string> keys{
      "coefficients", "ocamcalib_path", "clamp_fov_to_monotone", "binning", "focal_mm", "pitch_um",
      "fov_deg",      "table",          "width",                 "height",  "fx",       "fy",
      "cx",           "cy",             "skew",                  "model"};
  return keys;
}

// The keys a calibration file sets; giving one beside `calibration` is an error.
const std::vector<std::string>& calibrated_keys() {
  static const std::vector<std::string> keys{"lens_preset", "sensor_preset", "model", "width", "height",
                                             "focal_mm",    "pitch_um",      "fx",    "fy",    "cx",
                                             "cy",          "skew",          "coefficients", "table", "ocamcalib_path"};
  return keys;
}

// Whether `text` is UTF-8 (TOML's strings must be, and the description carries the text).
bool is_utf8(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto b = static_cast<unsigned char>(text[i]);
    const int n = b < 0x80 ? 0 : (b >> 5) == 0x6 ? 1 : (b >> 4) == 0xE ? 2 : (b >> 3) == 0x1E ? 3 : -1;
    if (n < 0 || i + n >= text.size()) return false;
    for (int k = 1; k <= n; ++k)
      if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) return false;
    i += n + 1;
  }
  return true;
}

// A make_lens error names a field; report it at that key of the table (or at `fallback`, or at
// the table).
[[noreturn]] void fail_lens(const Fields& c, const std::string& message, std::string_view fallback = "model") {
  std::string key;
  std::size_t best = std::string::npos;
  for (const std::string& k : lens_keys()) {
    const std::size_t at = message.find(k);
    if (at < best) best = at, key = k;
  }
  if (key == "cx" && message.find("cy") != std::string::npos && message.find("cx") == std::string::npos) key = "cy";
  c.fail(key.empty() || !c.has(key) ? fallback : std::string_view(key), message);
}

// Heading, tilt and roll of a world_from_camera rotation (inverse of
// world_from_heading_tilt_roll): tilt from the optical axis' elevation, heading from
// camera::heading_deg_of, roll from what is left.
void angles_of(const Eigen::Matrix3d& r, CameraSpec& s) {
  s.tilt_deg = std::acos(std::clamp(r(2, 2), -1.0, 1.0)) / kRadPerDeg;
  s.heading_deg = camera::heading_deg_of(r);
  const Eigen::Matrix3d without_roll = camera::world_from_heading_tilt_roll(s.heading_deg, s.tilt_deg, 0);
  const Eigen::Matrix3d roll = without_roll.transpose() * r;  // = Rz(ρ)
  s.roll_deg = std::atan2(roll(1, 0), roll(0, 0)) / kRadPerDeg;
  if (std::abs(s.roll_deg) < 1e-12) s.roll_deg = 0;
}

std::string canonical_description(const CameraSpec& s, const std::string& transport) {
  const camera::LensSpec& l = s.lens;
  std::ostringstream os;
  os.precision(17);
  auto opt = [&os](const char* key, const std::optional<double>& v) {
    if (v) os << key << " = " << *v << "\n";
  };
  if (s.calibration) {
    // The calibration's own text, so that the stack needs no file; the path is only a label.
    const camera::Calibration& cal = *s.calibration;
    os << "calibration = " << toml_quoted(cal.name) << "\ncalibration_format = \"" << cal.format << "\"\n";
    if (!cal.camera.empty()) os << "calibration_camera = " << toml_quoted(cal.camera) << "\n";
    os << "calibration_text = " << toml_quoted(cal.text) << "\n";
    opt("fov_deg", l.fov_deg);
    if (l.clamp_fov_to_monotone) os << "clamp_fov_to_monotone = true\n";
    if (l.binning != 1) os << "binning = " << l.binning << "\n";
    os << "heading_deg = " << s.heading_deg << "\ntilt_deg = " << s.tilt_deg << "\nroll_deg = " << s.roll_deg
       << "\ntransport = \"" << transport << "\"\n";
    return os.str();
  }
  os << "model = \"" << l.model << "\"\n";
  if (l.width) os << "width = " << l.width << "\nheight = " << l.height << "\n";
  opt("fx", l.fx);
  opt("fy", l.fy);
  opt("focal_mm", l.focal_mm);
  opt("pitch_um", l.pitch_um);
  opt("cx", l.cx);
  opt("cy", l.cy);
  opt("fov_deg", l.fov_deg);
  opt("skew", l.skew);
  if (!l.coefficients.empty()) {
    os << "coefficients = [";
    for (std::size_t i = 0; i < l.coefficients.size(); ++i) os << (i ? ", " : "") << l.coefficients[i];
    os << "]\n";
  }
  if (!l.table.empty()) {
    os << "table = [";
    for (std::size_t i = 0; i < l.table.size(); ++i) {
      os << (i ? ", " : "") << "[" << l.table[i].first << ", " << l.table[i].second << "]";
    }
    os << "]\n";
  }
  if (!l.ocamcalib_path.empty()) os << "ocamcalib_path = \"" << l.ocamcalib_path << "\"\n";
  if (l.clamp_fov_to_monotone) os << "clamp_fov_to_monotone = true\n";
  if (l.binning != 1) os << "binning = " << l.binning << "\n";
  os << "heading_deg = " << s.heading_deg << "\ntilt_deg = " << s.tilt_deg << "\nroll_deg = " << s.roll_deg
     << "\ntransport = \"" << transport << "\"\n";
  return os.str();
}

// `calibration` (a file) or `calibration_text` (its contents inline, as a stack header holds
// them) with `calibration_format` and `calibration_camera`: the lens as the file describes it.
camera::Calibration read_calibration(Fields& c) {
  camera::Calibration cal;
  const std::string at = c.has("calibration_text") ? "calibration_text" : "calibration";
  if (!c.has("calibration_format")) {
    std::string legal;
    for (auto f : camera::calibration_formats()) legal += (legal.empty() ? "" : ", ") + std::string(f);
    c.fail(at, "needs calibration_format (one of " + legal + ")");
  }
  std::vector<std::string> formats;
  for (std::string_view f : camera::calibration_formats()) formats.emplace_back(f);
  cal.format = c.choice("calibration_format", "", formats);
  if (const toml::node* n = c.node("calibration_camera")) {
    if (const auto i = n->value_exact<int64_t>()) {
      cal.camera = std::to_string(*i);
    } else if (const auto str = n->value_exact<std::string>()) {
      cal.camera = *str;
    } else {
      c.fail("calibration_camera", "expected a camera id: an integer (COLMAP, basalt) or a string (Kalibr's \"cam0\")");
    }
  }
  const std::optional<std::string> path = c.optional_string("calibration");
  if (path) {
    std::filesystem::path p(*path);
    if (p.is_relative()) p = std::filesystem::path(c.loc("calibration").file).parent_path() / p;
    cal.name = std::filesystem::absolute(p).lexically_normal().string();
  }
  if (std::optional<std::string> text = c.optional_string("calibration_text")) {
    cal.text = *text;
    if (!path) cal.name = "calibration_text";
  } else {
    std::ifstream in(cal.name, std::ios::binary);
    if (!std::filesystem::is_regular_file(cal.name) || !in) c.fail("calibration", "no such file: " + cal.name);
    std::ostringstream contents;
    contents << in.rdbuf();
    cal.text = contents.str();
  }
  if (!is_utf8(cal.text)) c.fail(c.has("calibration_text") ? "calibration_text" : "calibration", cal.name + ": not UTF-8 text");
  for (const std::string& k : calibrated_keys())
    if (c.has(k)) c.fail(k, "not with a calibration: " + cal.name + " sets the lens (fov_deg or image_circle_px, clamp_fov_to_monotone and binning may be given)");
  return cal;
}

camera::LensSpec read_lens(Fields& c) {
  camera::LensSpec l;
  // Presets give defaults; every explicit key overrides them.
  if (std::optional<std::string> lens_name = c.optional_string("lens_preset")) {
    const std::string sensor_name = c.string("sensor_preset", "sony_imx250mzr");
    try {
      l = camera::lens_spec(camera::lens_preset(*lens_name), camera::sensor_preset(sensor_name));
    } catch (const std::invalid_argument& e) {
      const bool sensor_bad = std::string(e.what()).find(sensor_name) != std::string::npos &&
                              std::string(e.what()).find(*lens_name) == std::string::npos;
      c.fail(sensor_bad ? "sensor_preset" : "lens_preset", e.what());
    }
  } else if (std::optional<std::string> sensor_name = c.optional_string("sensor_preset")) {
    try {
      const camera::SensorPreset& p = camera::sensor_preset(*sensor_name);
      l.width = p.width;
      l.height = p.height;
      l.pitch_um = p.pitch_um;
    } catch (const std::invalid_argument& e) {
      c.fail("sensor_preset", e.what());
    }
  }

  std::vector<std::string> models;
  for (std::string_view m : camera::lens_model_names()) models.emplace_back(m);
  l.model = c.choice("model", l.model.empty() ? "equidistant" : l.model, models);
  const camera::LensModel& entry = *camera::find_lens_model(l.model);
  l.width = static_cast<int>(c.integer("width", l.width, 1, 65536));
  l.height = static_cast<int>(c.integer("height", l.height, 1, 65536));
  if (!entry.size_from_file) {
    if (!l.width) c.fail("width", "missing (image width in pixels)");
    if (!l.height) c.fail("height", "missing (image height in pixels)");
  }
  if (std::optional<double> v = c.optional_number("focal_mm", 1e-3, 1e4)) l.focal_mm = v, l.fx.reset();
  if (std::optional<double> v = c.optional_number("pitch_um", 1e-2, 1e3)) l.pitch_um = v;
  if (std::optional<double> v = c.optional_number("fx", 1e-3, 1e7)) {
    l.fx = v;
    if (!c.has("focal_mm")) l.focal_mm.reset();
    if (!c.has("pitch_um") && !entry.pitch_converts_mm) l.pitch_um.reset();
  }
  if (std::optional<double> v = c.optional_number("fy", 1e-3, 1e7)) l.fy = v;
  if (std::optional<double> v = c.optional_number("skew", -1e7, 1e7)) l.skew = v;
  if (l.width) {
    if (std::optional<double> v = c.optional_number("cx", -0.5, l.width - 0.5)) l.cx = v;
    if (std::optional<double> v = c.optional_number("cy", -0.5, l.height - 0.5)) l.cy = v;
  }
  // The ideal fisheye mappings image a hemisphere unless told otherwise; the other models need
  // their field of view said (a perspective lens cannot reach 90°).
  if (std::optional<double> v = c.optional_number("fov_deg", 1, 360)) {
    l.fov_deg = v;
  } else if (!l.fov_deg && entry.hemisphere_default) {
    l.fov_deg = 180;
  }
  if (c.has("coefficients")) l.coefficients = c.numbers("coefficients", {});
  if (c.has("table")) {
    const std::vector<Fields::Row> rows = c.rows("table", 2);
    l.table.clear();
    for (const Fields::Row& r : rows) l.table.emplace_back(r[0], r[1]);
  }
  if (std::optional<std::string> p = c.optional_string("ocamcalib_path")) {
    // Relative to the scene file; stored absolute so that a stack's header rebuilds the lens.
    std::filesystem::path path(*p);
    // Relative to the file that wrote the key (an included preset resolves against its own folder).
    if (path.is_relative()) path = std::filesystem::path(c.loc("ocamcalib_path").file).parent_path() / path;
    l.ocamcalib_path = std::filesystem::absolute(path).lexically_normal().string();
    if (!std::filesystem::exists(l.ocamcalib_path)) c.fail("ocamcalib_path", "no such file: " + l.ocamcalib_path);
  }
  l.clamp_fov_to_monotone = c.boolean("clamp_fov_to_monotone", false);
  l.binning = static_cast<int>(c.integer("binning", 1, 1, 64));
  return l;
}

// Orientation: heading/tilt/roll or a quaternion.
void read_orientation(Fields& c, CameraSpec& s) {
  const bool has_angles = c.has("heading_deg") || c.has("tilt_deg") || c.has("roll_deg");
  if (c.has("quaternion")) {
    if (has_angles) c.fail("quaternion", "give either 'quaternion' or heading_deg/tilt_deg/roll_deg, not both");
    const std::vector<double> q = c.numbers("quaternion", {});
    if (q.size() != 4) c.fail("quaternion", "needs 4 numbers [w, x, y, z] (world <- camera, Hamilton)");
    try {
      angles_of(camera::world_from_quaternion(q[0], q[1], q[2], q[3]), s);
    } catch (const std::invalid_argument& e) {
      c.fail("quaternion", e.what());
    }
  } else {
    s.heading_deg = c.number("heading_deg", 0, -360, 360);
    s.tilt_deg = c.number("tilt_deg", 0, 0, 180);
    s.roll_deg = c.number("roll_deg", 0, -360, 360);
  }
}

}  // namespace

CameraSpec read_camera(Fields& c) {
  CameraSpec s;
  camera::LensSpec& l = s.lens;
  const bool calibrated = c.has("calibration") || c.has("calibration_text");
  const std::string_view lens_at = c.has("calibration_text") ? "calibration_text" : "calibration";

  if (calibrated) {
    s.calibration = read_calibration(c);
    try {
      l = camera::lens_spec_from_calibration(*s.calibration);
    } catch (const std::invalid_argument& e) {
      c.fail(lens_at, e.what());
    }
    if (c.has("clamp_fov_to_monotone")) l.clamp_fov_to_monotone = c.boolean("clamp_fov_to_monotone", false);
    if (std::optional<double> v = c.optional_number("fov_deg", 1, 360)) l.fov_deg = v;
    // The image circle's radius (pixels of the calibration, about its principal point) instead of
    // the farthest sensor corner: a fisheye's corners are dark, and their angle may pass 180°.
    if (std::optional<double> r = c.optional_number("image_circle_px", 1e-3, 1e6)) {
      if (c.has("fov_deg")) c.fail("image_circle_px", "give either fov_deg or image_circle_px, not both");
      try {
        camera::fit_fov_to_image_circle(l, *r);
      } catch (const std::invalid_argument& e) {
        c.fail("image_circle_px", e.what());
      }
    }
    l.binning = static_cast<int>(c.integer("binning", 1, 1, 64));
  } else {
    if (c.has("image_circle_px")) c.fail("image_circle_px", "only with a calibration (a lens model takes fov_deg)");
    s.lens = read_lens(c);
    if (!l.ocamcalib_path.empty()) {
      // Keep the calibration file's text with the camera: a stack stays estimable when the file moves.
      camera::Calibration cal;
      cal.format = "ocamcalib";
      cal.name = l.ocamcalib_path;
      std::ifstream in(cal.name, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      cal.text = l.ocamcalib_text = text.str();
      if (!is_utf8(cal.text)) c.fail("ocamcalib_path", cal.name + ": not UTF-8 text");
      s.calibration = cal;
    }
  }
  read_orientation(c, s);
  const std::string transport = c.choice("transport", "meridional", {"meridional", "projected"});
  s.transport = transport == "projected" ? camera::Transport::projected : camera::Transport::meridional;
  c.finish();

  try {
    (void)camera::make_lens(l);
  } catch (const std::invalid_argument& e) {
    fail_lens(c, e.what(), calibrated ? lens_at : std::string_view("model"));
  }
  // The canonical description: every value explicit, so a stack rebuilds the exact camera.
  s.description = canonical_description(s, transport);
  return s;
}

CameraSpec parse_camera(const std::string& toml_text, const std::string& file_name) {
  const toml::table t = parse_toml(toml_text, file_name);
  Fields f(t, file_name, "camera");
  return read_camera(f);
}

std::shared_ptr<const camera::Camera> build_camera(const CameraSpec& s) {
  return std::make_shared<camera::Camera>(
      camera::make_lens(s.lens), camera::world_from_heading_tilt_roll(s.heading_deg, s.tilt_deg, s.roll_deg),
      s.transport);
}

}  // namespace skypol::scene
