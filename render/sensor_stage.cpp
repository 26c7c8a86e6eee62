#include "render/sensor_stage.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "stack/polarization_math.h"

namespace skypol::render {
namespace {

std::atomic<std::size_t> g_frames_metered{0};

// A band's S0–S2 channels as the demosaic's output planes: their storage is reused (moved out of
// the frame and back by finish_band), so a frame the renderer reuses costs no allocation here.
camera::StokesPlanes take_planes(const std::string& band, stack::Frame& frame) {
  return {std::move(frame.channel("S0." + band)), std::move(frame.channel("S1." + band)),
          std::move(frame.channel("S2." + band))};
}

// Masked pixels hold zeros; the others get DoLP and AoLP from the measured Stokes.
void finish_band(const std::string& band, const std::vector<float>* mask, camera::StokesPlanes&& measured,
                 stack::Frame& frame) {
  const std::size_t n = measured.s0.size();
  if (mask) {
    for (std::size_t i = 0; i < n; ++i) {
      if ((*mask)[i] == 0.0f) measured.s0[i] = measured.s1[i] = measured.s2[i] = 0.0f;
    }
  }
  if (frame.has("DoLP." + band)) {
    std::vector<float>& dolp = frame.channel("DoLP." + band);
    for (std::size_t i = 0; i < n; ++i) dolp[i] = stack::dolp_of(measured.s0[i], measured.s1[i], measured.s2[i]);
  }
  if (frame.has("AoLP." + band)) {
    std::vector<float>& aolp = frame.channel("AoLP." + band);
    for (std::size_t i = 0; i < n; ++i) aolp[i] = stack::aolp_of(measured.s1[i], measured.s2[i]);
  }
  if (frame.has(band)) frame.channel(band) = measured.s0;  // the R, G, B display channels
  frame.channel("S0." + band) = std::move(measured.s0);
  frame.channel("S1." + band) = std::move(measured.s1);
  frame.channel("S2." + band) = std::move(measured.s2);
}

}  // namespace

std::vector<std::string> sensor_inputs(const std::vector<std::string>& bands) {
  std::vector<std::string> names;
  for (const std::string& b : bands) {
    for (const char* s : {"S0.", "S1.", "S2."}) names.push_back(s + b);
  }
  return names;
}

std::vector<std::string> kept_channels(std::vector<std::string> rendered, const std::vector<std::string>& asked,
                                       bool has_sensor) {
  const auto has = [](const std::vector<std::string>& v, const char* c) { return std::find(v.begin(), v.end(), c) != v.end(); };
  if (has(asked, "raw")) rendered.emplace_back("raw");
  if (has_sensor && has(rendered, "mask")) rendered.emplace_back("clipped");
  return rendered;
}

std::vector<std::uint8_t> sky_pixels(const camera::Camera& camera) {
  const int w = camera.width(), h = camera.height();
  std::vector<std::uint8_t> sky(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
  tbb::parallel_for(0, h, [&](int y) {
    thread_local std::vector<float> planes;
    const auto n = static_cast<std::size_t>(w);
    planes.resize(7 * n);
    float* p = planes.data();
    camera.ray_row(y, 0, n, {p, p + n, p + 2 * n, p + 3 * n, p + 4 * n, p + 5 * n, p + 6 * n});
    const float* dz = p + 2 * n;
    const float* valid = p + 6 * n;
    for (std::size_t x = 0; x < n; ++x) sky[static_cast<std::size_t>(y) * n + x] = valid[x] > 0 && dz[x] > 0;
  });
  return sky;
}

double meter_exposure_us(const scene::SensorSpec& sensor, const std::vector<std::string>& bands,
                         const stack::Frame& frame, std::span<const std::uint8_t> sky) {
  if (!sensor.auto_exposure) throw std::invalid_argument("sensor: metering needs auto exposure");
  const camera::DofpSensor& d = sensor.dofp;
  const int w = frame.width, h = frame.height;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (!sky.empty() && sky.size() != n) throw std::invalid_argument("sensor: the meter's sky region differs in size");
  const bool colour = d.color_filter != camera::ColorFilter::none;
  if (bands.size() != (colour ? 3u : 1u)) throw std::invalid_argument("sensor: the meter needs the sensor's bands");
  ++g_frames_metered;
  const std::vector<float>* mask = frame.has("mask") ? &frame.channel("mask") : nullptr;
  std::array<const std::vector<float>*, 3> s0{};
  for (std::size_t b = 0; b < bands.size(); ++b) s0[b] = &frame.channel("S0." + bands[b]);
  // The values are reordered by the percentile: a per-thread buffer, reused frame after frame.
  thread_local std::vector<float> values;
  values.clear();
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      if ((mask && !((*mask)[i] > 0.0f)) || (!sky.empty() && !sky[i])) continue;
      const int b = colour ? camera::band_of_pixel(d, y, x) : 0;
      const double v = double{(*s0[static_cast<std::size_t>(b)])[i]} * (colour ? d.band_response[static_cast<std::size_t>(b)] : 1.0);
      if (std::isfinite(v)) values.push_back(static_cast<float>(v));
    }
  }
  return camera::metered_exposure_us(d, *sensor.auto_exposure, camera::percentile_of(values, sensor.auto_exposure->percentile));
}

std::size_t frames_metered() { return g_frames_metered.load(); }

stack::PolarizerAngles polarizer_angles(const scene::SensorSpec& sensor) {
  const auto& e = sensor.dofp.angle_error_deg;
  const bool at_nominal = std::all_of(e.begin(), e.end(), [](double a) { return a == 0; });
  return sensor.demosaic == camera::Demosaic::calibrated || at_nominal ? stack::PolarizerAngles::calibrated
                                                                        : stack::PolarizerAngles::nominal;
}

void apply_sensor(const scene::SensorSpec& sensor, const std::vector<std::string>& bands, std::uint64_t frame_index,
                  stack::Frame& frame, bool keep_raw, std::span<const std::uint8_t> sky) {
  if (frame.width != sensor.dofp.width || frame.height != sensor.dofp.height) {
    throw std::invalid_argument("sensor: the frame's size differs from the sensor's");
  }
  // The meter reads the ideal frame, before the mask is eroded and any noise; the frame is then
  // taken at its exposure. Without auto exposure the sensor is used as it is, unread.
  camera::DofpSensor metered;
  if (sensor.auto_exposure) {
    metered = sensor.dofp;
    metered.exposure_us = meter_exposure_us(sensor, bands, frame, sky);
  }
  const camera::DofpSensor& d = sensor.auto_exposure ? metered : sensor.dofp;
  frame.exposure_us = d.exposure_us;
  frame.polarizer_angles = polarizer_angles(sensor);
  frame.zero_outside = 0;  // noise and the eroded mask change pixels outside the circle too
  // The bilinear demosaic reads a pixel's neighbours up to camera::demosaic_reach away (1 on a mono
  // sensor, 3 on a colour one): a pixel that near one that sees no sky mixes in darkness, so it is
  // masked too (the mask is eroded by the reach).
  std::vector<float>* mask = frame.has("mask") ? &frame.channel("mask") : nullptr;
  if (mask) camera::erode_mask(*mask, frame.width, frame.height, camera::demosaic_reach(d));
  // One raw buffer per thread, reused frame after frame (a stack's frames share one size).
  thread_local std::vector<std::uint16_t> raw;
  if (d.color_filter == camera::ColorFilter::none) {
    if (bands.size() != 1) throw std::invalid_argument("sensor: a mono sensor records one band");
    const std::string& b = bands[0];
    camera::simulate_raw_into(d, frame.channel("S0." + b), frame.channel("S1." + b), frame.channel("S2." + b),
                              frame_index, raw);
    camera::StokesPlanes planes = take_planes(b, frame);  // the raw frame no longer needs them
    camera::demosaic_bilinear_into(d, raw, sensor.demosaic, planes);
    finish_band(b, mask, std::move(planes), frame);
    // A pixel whose demosaic read a clipped raw value sees sky, but not a Stokes vector anyone
    // should fit: masked, its S0 kept (the picture shows the glare), and marked in "clipped", sky
    // the camera saw but could not read, which the cloud gate counts (skypole/cloud_share.h).
    if (mask) camera::mask_clipped(camera::clipped_pixels(d, raw), *mask, frame.channels["clipped"]);
    if (keep_raw) frame.channels["raw"].assign(raw.begin(), raw.end());
    return;
  }
  if (bands != std::vector<std::string>{"R", "G", "B"}) {
    throw std::invalid_argument("sensor: a colour sensor records bands R, G, B");
  }
  std::array<camera::BandStokes, 3> rgb;
  for (std::size_t i = 0; i < 3; ++i) {
    rgb[i] = {frame.channel("S0." + bands[i]), frame.channel("S1." + bands[i]), frame.channel("S2." + bands[i])};
  }
  camera::simulate_raw_color_into(d, rgb, frame_index, raw);
  std::array<camera::StokesPlanes, 3> measured;
  for (std::size_t i = 0; i < 3; ++i) measured[i] = take_planes(bands[i], frame);
  camera::demosaic_color_bilinear_into(d, raw, sensor.demosaic, measured);
  for (std::size_t i = 0; i < 3; ++i) finish_band(bands[i], mask, std::move(measured[i]), frame);
  if (mask) camera::mask_clipped(camera::clipped_pixels(d, raw), *mask, frame.channels["clipped"]);
  if (keep_raw) frame.channels["raw"].assign(raw.begin(), raw.end());
}

}  // namespace skypol::render
