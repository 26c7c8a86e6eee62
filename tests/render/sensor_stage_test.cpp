// The sensor stage: a uniform polarized field through the DoFP sensor comes back with its DoLP
// and AoLP (the AoLP's sign catches a mosaic or S2 sign error), noise is keyed by the frame index,
// masked pixels stay zero, and pixels whose demosaic read a clipped raw value are masked.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include <filesystem>

#include "render/pipeline.h"
#include "render/sensor_stage.h"
#include "stack/stack_io.h"

using namespace skypol;

namespace {

stack::Frame uniform_frame(int w, int h, float s0, float s1, float s2) {
  stack::Frame f;
  f.width = w;
  f.height = h;
  const auto n = static_cast<std::size_t>(w * h);
  f.channels["S0.Y"] = std::vector<float>(n, s0);
  f.channels["S1.Y"] = std::vector<float>(n, s1);
  f.channels["S2.Y"] = std::vector<float>(n, s2);
  f.channels["DoLP.Y"] = std::vector<float>(n, 0);
  f.channels["AoLP.Y"] = std::vector<float>(n, 0);
  f.channels["mask"] = std::vector<float>(n, 1);
  return f;
}

scene::SensorSpec sensor(int w, int h) {
  scene::SensorSpec s;
  s.dofp.width = w;
  s.dofp.height = h;
  s.dofp.exposure_us = 1000;
  s.dofp.electrons_per_radiance_s = 5e6;  // S0 = 1 → 5000 e- through an ideal polarizer
  s.dofp.gain_dn_per_e = 0.25;
  s.dofp.full_well_e = 1e5;
  s.dofp.adc_bits = 16;
  return s;
}

double mean_inner(const std::vector<float>& v, int w, int h) {
  double sum = 0;
  int n = 0;
  for (int y = 2; y < h - 2; ++y) {
    for (int x = 2; x < w - 2; ++x, ++n) sum += static_cast<double>(v[static_cast<std::size_t>(y * w + x)]);
  }
  return sum / n;
}

}  // namespace

TEST_CASE("a noise-free sensor returns the field's DoLP and AoLP", "[sensor]") {
  scene::SensorSpec s = sensor(32, 32);
  s.dofp.shot_noise = false;
  s.dofp.read_noise_e = 0;
  s.dofp.dark_current_e_s = 0;
  // DoLP 0.5, AoLP ½·atan2(0.4, 0.3) = 26.57°.
  stack::Frame f = uniform_frame(32, 32, 1.0f, 0.3f, 0.4f);
  render::apply_sensor(s, {"Y"}, 0, f, /*keep_raw=*/true);
  // Pixel (0,0) sits behind the 90° polarizer: ½(S0 − S1) = 0.35 → 1750 e- → 437.5 DN; (0,1) the
  // 45° one: ½(S0 + S2) = 0.7 → 875 DN.
  const std::vector<float>& raw = f.channel("raw");
  CHECK(raw[0] == Approx(437.5).margin(0.5));
  CHECK(raw[1] == Approx(875).margin(0.5));
  CHECK(mean_inner(f.channel("DoLP.Y"), 32, 32) == Approx(0.5).margin(2e-3));  // 16-bit quantization
  CHECK(mean_inner(f.channel("AoLP.Y"), 32, 32) == Approx(0.5 * std::atan2(0.4, 0.3)).margin(2e-3));
  CHECK(mean_inner(f.channel("S0.Y"), 32, 32) == Approx(1.0).margin(2e-3));
}

TEST_CASE("shot noise averages out, is keyed by the frame index, and spares masked pixels", "[sensor]") {
  const scene::SensorSpec s = sensor(64, 64);
  stack::Frame a = uniform_frame(64, 64, 1.0f, -0.2f, 0.1f), b = a, c = a;
  for (int i = 0; i < 64; ++i) a.channel("mask")[static_cast<std::size_t>(i)] = 0;  // first row: occluded
  render::apply_sensor(s, {"Y"}, 3, a);
  render::apply_sensor(s, {"Y"}, 3, b);
  render::apply_sensor(s, {"Y"}, 4, c);
  // 5000 e- per pixel: DoLP's noise is ~1 %, its mean over ~3600 pixels within 0.2 % of 0.2236.
  CHECK(mean_inner(a.channel("DoLP.Y"), 64, 64) == Approx(std::hypot(0.2, 0.1)).margin(3e-3));
  CHECK(mean_inner(a.channel("AoLP.Y"), 64, 64) == Approx(0.5 * std::atan2(0.1, -0.2)).margin(5e-3));
  const auto& da = a.channel("DoLP.Y");
  CHECK(std::vector<float>(da.begin() + 128, da.end()) ==
        std::vector<float>(b.channel("DoLP.Y").begin() + 128, b.channel("DoLP.Y").end()));
  CHECK(c.channel("DoLP.Y") != b.channel("DoLP.Y"));
  for (int i = 0; i < 128; ++i) {  // the occluded row and, eroded, the row below it
    CHECK(a.channel("S0.Y")[static_cast<std::size_t>(i)] == 0.0f);
    CHECK(da[static_cast<std::size_t>(i)] == 0.0f);
    CHECK(a.channel("mask")[static_cast<std::size_t>(i)] == 0.0f);
  }
  CHECK(a.channel("mask")[128] == 1.0f);
}

TEST_CASE("with a sensor, what sees no sky is zero even when the file keeps no mask", "[sensor]") {
  const scene::Scene scene = scene::parse_scene(R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336
[time]
instants = ["2022-09-23T10:00:00Z", "2022-09-23T11:00:00Z"]
[camera]
lens_preset = "fujinon_fe185c057ha1"
binning = 16
[sensor]
preset = "sony_imx250mzr"
[output]
channels = ["DoLP"]
)", "nomask.toml");
  const std::string path = (std::filesystem::temp_directory_path() / "skypol-sensor-nomask.exr").string();
  render::render_scene(scene, path);
  const stack::Stack stack = stack::read_stack(path);
  std::filesystem::remove(path);
  // Both parts: the second is rendered into the first's frame after the sensor wrote it (the
  // sensor stage resets the frame's zero_outside token, so the renderer clears again).
  REQUIRE(stack.frames.size() == 2);
  for (const stack::Frame& f : stack.frames) {
  CHECK_FALSE(f.has("mask"));
  const std::vector<float>& dolp = f.channel("DoLP.Y");
  // The first and last rows lie outside the image circle: no dark-noise "polarization" there.
  const auto w = static_cast<std::size_t>(f.width);
  CHECK(std::count(dolp.begin(), dolp.begin() + static_cast<long>(w), 0.0f) == static_cast<long>(w));
  CHECK(std::count(dolp.end() - static_cast<long>(w), dolp.end(), 0.0f) == static_cast<long>(w));
  const auto centre = static_cast<std::size_t>(f.height / 2 * f.width + f.width / 2);
  CHECK(dolp[centre] > 0.05f);  // the sky at the zenith is polarized
  }
}

TEST_CASE("pixels whose demosaic read a clipped raw value are masked, their S0 kept", "[sensor]") {
  scene::SensorSpec s = sensor(32, 16);
  s.dofp.shot_noise = false;
  s.dofp.read_noise_e = 0;
  // Columns 0–9 at S0 = 30 (75,000 e- behind every polarizer at DoLP 0: within the 1e5 e- well),
  // columns 10–15 at DoLP 0.8 along 0° (the 0° polarizers, odd rows and columns of the
  // {90, 45, 135, 0} mosaic, see 135,000 e-: clipped, the others not), the rest dim. Only the
  // clipped columns 11, 13, 15 and the demosaic's reach of one pixel either side are masked.
  stack::Frame f = uniform_frame(32, 16, 1.0f, 0.0f, 0.0f);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const auto i = static_cast<std::size_t>(y * 32 + x);
      f.channel("S0.Y")[i] = 30.0f;
      if (x >= 10) f.channel("S1.Y")[i] = 24.0f;
    }
  // Pixel (13, 8) sees no sky (an occluder): it and its eroded ring are masked, but not as clipped sky.
  f.channel("mask")[static_cast<std::size_t>(8 * 32 + 13)] = 0.0f;
  render::apply_sensor(s, {"Y"}, 0, f);
  for (int y = 1; y < 15; ++y)
    for (int x = 1; x < 31; ++x) {
      INFO("pixel (" << x << ", " << y << ")");
      const auto i = static_cast<std::size_t>(y * 32 + x);
      const bool unseen = std::abs(x - 13) <= 1 && std::abs(y - 8) <= 1;
      const bool clipped = x >= 10 && x <= 16 && !unseen;
      CHECK(f.channel("mask")[i] == (clipped || unseen ? 0.0f : 1.0f));
      CHECK(f.channel("clipped")[i] == (clipped ? 1.0f : 0.0f));  // the sky masked for clipping
      if (!unseen) CHECK(f.channel("S0.Y")[i] > 0.5f);  // the glare stays in the picture
    }
  // Where clipped, the DoLP reads low (0.8 true): the Stokes vector the mask keeps out.
  CHECK(f.channel("DoLP.Y")[static_cast<std::size_t>(4 * 32 + 13)] < 0.7f);
}
