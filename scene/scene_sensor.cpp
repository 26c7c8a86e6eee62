// The [sensor] section: a division-of-focal-plane polarization sensor (camera/dofp_sensor.h).
// Its size is the camera's (after binning); a preset gives the noise figures, keys override them.
#include <array>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string_view>
#include <vector>

#include "camera/dofp_sensor.h"

#include "camera/presets.h"
#include "scene/scene.h"

namespace skypol::scene {
namespace {

std::array<double, 4> four(Fields& f, std::string_view key, std::array<double, 4> fallback) {
  if (!f.has(key)) {
    (void)f.numbers(key, {});  // mark as known
    return fallback;
  }
  const std::vector<double> v = f.numbers(key, {});
  if (v.size() != 4) f.fail(key, "needs 4 numbers, for pixels (0,0) (0,1) (1,0) (1,1) of each 2x2 block");
  return {v[0], v[1], v[2], v[3]};
}

constexpr std::array<std::string_view, 5> kMeterKeys = {"auto_exposure_percentile", "auto_exposure_target",
                                                        "auto_exposure_min_us", "auto_exposure_max_us",
                                                        "auto_exposure_step_us"};

// exposure = "fixed" (exposure_us, every frame) or "auto" (the meter's keys). A key of the other
// mode is an error at that key: it would be silently ignored.
void read_exposure(Fields& f, SensorSpec& s) {
  const bool automatic = f.choice("exposure", "fixed", {"fixed", "auto"}) == "auto";
  if (!automatic) {
    for (std::string_view key : kMeterKeys)
      if (f.has(key)) f.fail(key, "is a setting of the meter: it needs exposure = \"auto\"");
    s.dofp.exposure_us = f.number("exposure_us", s.dofp.exposure_us, 1e-3, 1e9);
    return;
  }
  if (f.has("exposure_us")) {
    f.fail("exposure_us", "is the fixed exposure; with exposure = \"auto\" the meter sets each frame's "
                          "(auto_exposure_min_us and auto_exposure_max_us bound it)");
  }
  camera::AutoExposure m;
  m.percentile = f.number("auto_exposure_percentile", m.percentile, 0, 100);
  m.target = f.number("auto_exposure_target", m.target, 0, 1);
  m.min_us = f.number("auto_exposure_min_us", m.min_us, 1e-3, 1e9);
  m.max_us = f.number("auto_exposure_max_us", m.max_us, 1e-3, 1e9);
  m.step_us = f.number("auto_exposure_step_us", m.step_us, 0, 1e9);
  const auto g = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  if (m.max_us < m.min_us) {
    f.fail(f.has("auto_exposure_max_us") ? "auto_exposure_max_us" : "auto_exposure_min_us",
           "the exposure range is empty: auto_exposure_min_us = " + g(m.min_us) + " is above auto_exposure_max_us = " +
               g(m.max_us) + " (default 1e7, 10 s)");
  }
  try {
    camera::validate(m);
  } catch (const std::invalid_argument& e) {
    // validate's messages start with the field: the key without its "auto_exposure_" prefix.
    const std::string msg = e.what();
    const std::string key = "auto_exposure_" + msg.substr(0, msg.find(' '));
    f.fail(key, msg);
  }
  s.auto_exposure = m;
}

}  // namespace

SensorSpec read_sensor(Fields& f, const CameraSpec& camera_spec) {
  SensorSpec s;
  camera::DofpSensor& d = s.dofp;
  if (std::optional<std::string> preset = f.optional_string("preset")) {
    try {
      d = camera::sensor_preset(*preset).dofp;
    } catch (const std::invalid_argument& e) {
      f.fail("preset", e.what());
    }
  }
  const camera::Intrinsics k = camera::make_lens(camera_spec.lens)->intrinsics();
  d.width = k.width;
  d.height = k.height;
  const std::string filter = f.choice("color_filter", d.color_filter == camera::ColorFilter::none ? "none" : "rggb_blocks",
                                      {"none", "rggb_blocks"});
  d.color_filter = filter == "none" ? camera::ColorFilter::none : camera::ColorFilter::rggb_blocks;
  const std::array<double, 4> mosaic = four(f, "mosaic_deg", d.mosaic_deg);
  d.mosaic_deg = mosaic;
  d.angle_error_deg = four(f, "angle_error_deg", d.angle_error_deg);
  if (f.has("band_response")) {
    const std::vector<double> r = f.numbers("band_response", {});
    if (r.size() != 3) f.fail("band_response", "needs 3 numbers (R, G, B)");
    d.band_response = {r[0], r[1], r[2]};
  } else {
    (void)f.numbers("band_response", {});
  }
  d.extinction_ratio = f.number("extinction_ratio", d.extinction_ratio, 1.0 + 1e-9, 1e12);
  read_exposure(f, s);
  d.electrons_per_radiance_s = f.number("electrons_per_radiance_s", d.electrons_per_radiance_s, 0, 1e15);
  d.gain_dn_per_e = f.number("gain_dn_per_e", d.gain_dn_per_e, 1e-6, 1e6);
  d.black_level_dn = f.number("black_level_dn", d.black_level_dn, 0, 65535);
  d.read_noise_e = f.number("read_noise_e", d.read_noise_e, 0, 1e6);
  d.dark_current_e_s = f.number("dark_current_e_s", d.dark_current_e_s, 0, 1e9);
  d.full_well_e = f.number("full_well_e", d.full_well_e, 1, 1e9);
  d.adc_bits = static_cast<int>(f.integer("adc_bits", d.adc_bits, 1, 16));
  d.shot_noise = f.boolean("shot_noise", d.shot_noise);
  d.prnu_rms = f.number("prnu_rms", d.prnu_rms, 0, 1);
  d.dsnu_e = f.number("dsnu_e", d.dsnu_e, 0, 1e6);
  d.seed = static_cast<std::uint64_t>(f.integer("seed", 0, 0, std::numeric_limits<long long>::max()));
  s.demosaic = f.choice("demosaic", "nominal", {"nominal", "calibrated"}) == "calibrated" ? camera::Demosaic::calibrated
                                                                                          : camera::Demosaic::nominal;
  f.finish();
  try {
    camera::validate(d);
  } catch (const std::invalid_argument& e) {
    // validate's messages start with the field, which is the key.
    const std::string msg = e.what();
    const std::string field = msg.substr(0, msg.find_first_of(" :"));
    f.fail(f.has(field) ? std::string_view(field) : std::string_view("preset"), msg);
  }
  // What only the sensor stage would find, found here before any work: the demosaic's demands on
  // the polarizer angles (nominal needs 0/45/90/135; calibrated needs angles that determine S1
  // and S2), checked by demosaicing a blank 4x4 mosaic of the same sensor.
  camera::DofpSensor probe = d;
  probe.width = probe.height = 4;
  probe.color_filter = camera::ColorFilter::none;
  try {
    const std::vector<std::uint16_t> blank(16, 0);
    (void)camera::demosaic_bilinear(probe, blank, s.demosaic);
  } catch (const std::invalid_argument& e) {
    f.fail(f.has("mosaic_deg") ? "mosaic_deg" : f.has("demosaic") ? "demosaic" : "preset",
           std::string(e.what()) + (s.demosaic == camera::Demosaic::calibrated ? " (demosaic = \"calibrated\")"
                                                                               : " (demosaic = \"nominal\")"));
  }
  if (d.color_filter != camera::ColorFilter::none && (d.width < 4 || d.height < 4)) {
    f.fail("color_filter", "a colour sensor needs an image of at least 4x4 pixels (the camera's is " +
                               std::to_string(d.width) + "x" + std::to_string(d.height) + ")");
  }
  return s;
}

}  // namespace skypol::scene
