#include "stack/capture_import.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fnmatch.h>
#include <map>
#include <optional>
#include <span>

#include "camera/dofp_sensor.h"
#include "camera/orientation.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/toml_fields.h"
#include "scene/truth.h"
#include "stack/capture_times.h"
#include "stack/polarization_math.h"
#include "stack/raw_frame.h"
#include "stack/stack_io.h"

namespace skypol::stack {
namespace {

namespace fs = std::filesystem;

// The [capture] table, checked.
struct CaptureSpec {
  std::vector<std::string> frames;  // resolved paths, sorted within each glob
  std::string times = "name";       // name, exif, csv
  std::string time_format = "*_%Y%m%dT%H%M%S*";
  std::string time_zone = "Z";
  std::string times_csv;
  std::string dark, flat;           // resolved paths, or empty
  std::string band = "Y";
  int right_shift = 0;
};

std::string resolve(const fs::path& base, const std::string& name) {
  const fs::path p(name);
  return (p.is_absolute() ? p : base / p).lexically_normal().string();
}

// A name with * ? [ is a glob over one folder (the folder part itself is literal); matches sorted,
// each named as resolve names a literal one. A pattern with no folder part, in a capture file named
// without one (`skypol import capture.toml`), lists the current folder.
std::vector<std::string> expand(scene::Fields& f, const fs::path& base, const std::string& pattern) {
  const std::string full = resolve(base, pattern);
  if (pattern.find_first_of("*?[") == std::string::npos) return {full};
  const fs::path folder = fs::path(full).parent_path();
  const fs::path dir = folder.empty() ? fs::path(".") : folder;
  const std::string leaf = fs::path(full).filename().string();
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file() && fnmatch(leaf.c_str(), e.path().filename().c_str(), 0) == 0) {
      out.push_back((folder / e.path().filename()).string());
    }
  }
  if (ec) f.fail("frames", "cannot list " + dir.string() + " (" + ec.message() + ")");
  if (out.empty()) f.fail("frames", "'" + pattern + "' matches no file (in " + dir.string() + ")");
  std::sort(out.begin(), out.end());
  return out;
}

CaptureSpec read_capture(scene::Fields& f, const fs::path& base) {
  CaptureSpec c;
  const std::vector<std::string> patterns = f.strings("frames", {});
  if (patterns.empty()) f.fail("frames", "missing: the raw frames, e.g. frames = [\"raw/*.png\"]");
  for (const std::string& p : patterns) {
    for (std::string& path : expand(f, base, p)) c.frames.push_back(std::move(path));
  }
  c.times = f.choice("times", c.times, {"name", "exif", "csv"});
  c.time_format = f.string("time_format", c.time_format);
  c.time_zone = f.string("time_zone", c.time_zone);
  if (c.times == "csv") {
    c.times_csv = resolve(base, f.required_string("times_csv"));
  } else if (f.has("times_csv")) {
    f.fail("times_csv", "given, but times = \"" + c.times + "\" (set times = \"csv\" to use it)");
  }
  if (auto d = f.optional_string("dark")) c.dark = resolve(base, *d);
  if (auto d = f.optional_string("flat")) c.flat = resolve(base, *d);
  c.band = f.string("band", c.band);
  c.right_shift = static_cast<int>(f.integer("right_shift", 0, 0, 15));
  f.finish();
  return c;
}

// A dark or flat frame: the camera's size, finite values (a flat also positive).
std::vector<double> correction(const std::string& path, int width, int height, bool flat) {
  RawFrame r = read_raw_frame(path);
  if (r.width != width || r.height != height) {
    throw scene::SceneError(scene::FileLoc{path, 0, 0}, "is " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                                                            ", the camera is " + std::to_string(width) + "x" +
                                                            std::to_string(height));
  }
  for (double v : r.values) {
    if (!std::isfinite(v) || (flat && v <= 0)) {
      throw scene::SceneError(scene::FileLoc{path, 0, 0}, flat ? "a flat field must hold finite positive values"
                                                               : "a dark frame must hold finite values");
    }
  }
  return std::move(r.values);
}

// Pixels the lens images (a ray exists), eroded by the demosaic's reach as the sensor stage erodes
// its mask: the bilinear demosaic mixes each pixel's neighbours (camera::demosaic_reach).
std::vector<float> lens_mask(const camera::Camera& cam, const camera::DofpSensor& sensor) {
  const int w = cam.width(), h = cam.height();
  std::vector<float> mask(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) mask[static_cast<std::size_t>(y) * w + x] = cam.ray(Eigen::Vector2d(x, y)) ? 1.0f : 0.0f;
  camera::erode_mask(mask, w, h, camera::demosaic_reach(sensor));
  return mask;
}

// One band's measured Stokes into the frame, zero outside the mask, with DoLP and AoLP.
void put_band(const std::string& band, camera::StokesPlanes&& p, const std::vector<float>& mask, bool display,
              Frame& frame) {
  const std::size_t n = mask.size();
  std::vector<float> dolp(n), aolp(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (mask[i] == 0.0f) p.s0[i] = p.s1[i] = p.s2[i] = 0.0f;
    dolp[i] = dolp_of(p.s0[i], p.s1[i], p.s2[i]);
    aolp[i] = aolp_of(p.s1[i], p.s2[i]);
  }
  if (display) frame.channels[band] = p.s0;
  frame.channels["S0." + band] = std::move(p.s0);
  frame.channels["S1." + band] = std::move(p.s1);
  frame.channels["S2." + band] = std::move(p.s2);
  frame.channels["DoLP." + band] = std::move(dolp);
  frame.channels["AoLP." + band] = std::move(aolp);
}

}  // namespace

ImportReport import_capture(const std::string& capture_path, const std::string& out_path,
                            const std::vector<scene::Override>& overrides,
                            const std::function<void(std::size_t, std::size_t)>& progress) {
  const scene::SceneSource source = scene::load_scene_source(capture_path, overrides);
  const fs::path base = fs::path(capture_path).parent_path();
  scene::Fields top(source.root, capture_path, "");

  std::optional<scene::Fields> cap = top.table("capture");
  if (!cap) top.fail("capture", "missing section [capture] (frames, times)");
  const CaptureSpec spec = read_capture(*cap, base);

  std::optional<sky::Site> site;
  if (std::optional<scene::Fields> s = top.table("site")) site = scene::read_site(*s);
  std::optional<scene::Fields> cam_table = top.table("camera");
  if (!cam_table) top.fail("camera", "missing section [camera] (the lens and its calibration, docs/scenes.md)");
  if (cam_table->has("heading_deg") || cam_table->has("quaternion")) {
    cam_table->fail(cam_table->has("heading_deg") ? "heading_deg" : "quaternion",
                    "a capture's heading is what `skypol estimate` finds: give tilt_deg and roll_deg only");
  }
  const scene::CameraSpec camera_spec = scene::read_camera(*cam_table);
  std::optional<scene::Fields> sensor_table = top.table("sensor");
  if (!sensor_table) {
    top.fail("sensor", "missing section [sensor] (the polarizer mosaic_deg, color_filter, adc_bits, black_level_dn, "
                       "… as in a scene, docs/scenes.md)");
  }
  const scene::SensorSpec sensor = scene::read_sensor(*sensor_table, camera_spec);
  if (!(sensor.dofp.electrons_per_radiance_s > 0)) {
    sensor_table->fail("electrons_per_radiance_s", "must be > 0 to turn DN into radiance (any value: units are relative)");
  }
  top.finish();
  const bool colour = sensor.dofp.color_filter != camera::ColorFilter::none;
  if (colour && cap->has("band")) cap->fail("band", "a colour sensor's bands are R, G, B");
  const std::vector<std::string> bands = colour ? std::vector<std::string>{"R", "G", "B"}
                                                : std::vector<std::string>{spec.band};

  const std::shared_ptr<const camera::Camera> cam = scene::build_camera(camera_spec);
  const int w = cam->width(), h = cam->height();
  const camera::DofpSensor& d = sensor.dofp;
  const double max_dn = std::ldexp(1.0, d.adc_bits) - 1;

  // Everything is read and checked before anything is written.
  std::map<std::string, sky::Instant> csv;
  if (spec.times == "csv") csv = read_times_csv(spec.times_csv, spec.time_zone);
  std::vector<double> dark, flat;
  if (!spec.dark.empty()) dark = correction(spec.dark, w, h, false);
  if (!spec.flat.empty()) flat = correction(spec.flat, w, h, true);
  // With a dark frame, the sensor's own black level and mean dark signal are put back after the
  // subtraction, because the demosaic removes them again (camera/dofp_sensor.h).
  const double offset_dn = d.black_level_dn + d.gain_dn_per_e * d.dark_current_e_s * d.exposure_us * 1e-6;

  std::vector<std::vector<std::uint16_t>> raws;  // as recorded; without corrections, what is demosaicked
  // With a dark or a flat frame: the corrected DN, in floating point (rounding them back to whole
  // DN would add up to 0.5 DN of error, more than a flat's percent-level corrections of a dim sky).
  std::vector<std::vector<float>> corrected;
  std::vector<std::vector<std::uint8_t>> clipped;  // per frame: camera::clipped_pixels
  std::vector<scene::Truth> truths;
  for (std::size_t i = 0; i < spec.frames.size(); ++i) {
    const std::string& path = spec.frames[i];
    const RawFrame r = read_raw_frame(path);
    if (r.width != w || r.height != h) {
      throw scene::SceneError(scene::FileLoc{path, 0, 0}, "is " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                                                              ", the [camera] is " + std::to_string(w) + "x" + std::to_string(h));
    }
    std::vector<std::uint16_t> dn = to_dn(r, path, spec.right_shift, max_dn);
    clipped.push_back(camera::clipped_pixels(d, dn));  // the camera's own readings, before corrections
    if (!dark.empty() || !flat.empty()) {
      std::vector<float> v(dn.size());
      for (std::size_t k = 0; k < dn.size(); ++k) {
        double x = dn[k];
        if (!dark.empty()) x = x - dark[k];
        if (!flat.empty()) x = x / flat[k];
        if (!dark.empty()) x += offset_dn;
        v[k] = static_cast<float>(x);
      }
      corrected.push_back(std::move(v));
      dn = {};
    }
    scene::Truth t;
    const std::string name = fs::path(path).filename().string();
    try {
      if (spec.times == "name") {
        t.time = time_from_name(name, spec.time_format, spec.time_zone);
      } else if (spec.times == "exif") {
        if (r.exif_time.empty()) throw std::invalid_argument("the file has no EXIF DateTimeOriginal or TIFF DateTime");
        t.time = time_from_exif(r.exif_time, spec.time_zone);
      } else {
        auto it = csv.find(name);
        if (it == csv.end()) it = csv.find(fs::relative(path, base).string());
        if (it == csv.end()) throw std::invalid_argument("not listed in " + spec.times_csv);
        t.time = it->second;
      }
    } catch (const std::invalid_argument& e) {
      throw scene::SceneError(scene::FileLoc{path, 0, 0}, std::string("time: ") + e.what());
    }
    if (!truths.empty() && !(truths.back().time < t.time)) {
      throw scene::SceneError(scene::FileLoc{path, 0, 0}, "time " + sky::format_iso8601(t.time) +
                                                              " is not after the previous frame's (" +
                                                              sky::format_iso8601(truths.back().time) +
                                                              "); frames are taken in file-name order");
    }
    t.tilt_deg = camera_spec.tilt_deg;
    t.roll_deg = camera_spec.roll_deg;
    t.world_from_camera = camera::world_from_heading_tilt_roll(0.0, t.tilt_deg, t.roll_deg);
    if (site) {
      t.site = *site;
      t.sun = sky::sun_position(*site, t.time);
      t.pole_enu = scene::visible_pole(site->latitude_deg);
      t.pole_is_north = site->latitude_deg >= 0;
    }
    truths.push_back(t);
    raws.push_back(std::move(dn));
  }

  const std::vector<float> mask = lens_mask(*cam, d);
  std::vector<std::string> channels;
  for (const std::string& b : bands) {
    for (const char* s : {"S0.", "S1.", "S2.", "DoLP.", "AoLP."}) channels.push_back(s + b);
    if (colour) channels.push_back(b);
  }
  channels.emplace_back("mask");
  channels.emplace_back("clipped");

  StackHeader header;
  header.bands = bands;
  header.camera_description = camera_spec.description;
  header.scene_text = source.text;
  header.sky_model = "capture";
  header.truth_known = false;
  header.site_known = site.has_value();
  // A capture's polarizers are at their nominal angles only as far as its owner has measured them.
  header.polarizer_angles =
      sensor.demosaic == camera::Demosaic::calibrated ? PolarizerAngles::calibrated : PolarizerAngles::nominal;
  // WriteOptions' defaults are the renders', so an imported stack and a rendered one of the same raw
  // frames hold the same values.
  write_stack(out_path, truths, channels, w, h, header, WriteOptions{}, [&](std::size_t i) {
    if (progress && i > 0) progress(i, truths.size());
    Frame f;
    f.width = w;
    f.height = h;
    f.truth = truths[i];
    const bool floating = !corrected.empty();
    if (!colour) {
      put_band(bands[0],
               floating ? camera::demosaic_bilinear(d, std::span<const float>(corrected[i]), sensor.demosaic)
                        : camera::demosaic_bilinear(d, std::span<const std::uint16_t>(raws[i]), sensor.demosaic),
               mask, false, f);
    } else {
      std::array<camera::StokesPlanes, 3> rgb =
          floating ? camera::demosaic_color_bilinear(d, std::span<const float>(corrected[i]), sensor.demosaic)
                   : camera::demosaic_color_bilinear(d, std::span<const std::uint16_t>(raws[i]), sensor.demosaic);
      for (std::size_t b = 0; b < 3; ++b) put_band(bands[b], std::move(rgb[b]), mask, true, f);
    }
    // As a render's sensor stage: a pixel whose demosaic read a clipped raw value is masked
    // (camera::clipped_pixels), its S0 kept, and channel "clipped" marks the sky masked so.
    camera::mask_clipped(clipped[i], f.channels["mask"] = mask, f.channels["clipped"]);
    std::vector<std::uint8_t>().swap(clipped[i]);
    std::vector<std::uint16_t>().swap(raws[i]);  // this frame's mosaic is no longer needed
    if (floating) std::vector<float>().swap(corrected[i]);
    return f;
  });
  if (progress) progress(truths.size(), truths.size());

  ImportReport report;
  report.frames = truths.size();
  report.width = w;
  report.height = h;
  report.bands = bands;
  report.site_known = site.has_value();
  return report;
}

}  // namespace skypol::stack
