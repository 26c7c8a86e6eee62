// The sensor stage: a uniform polarized field through the DoFP sensor comes back with its DoLP
// and AoLP (the AoLP's sign catches a mosaic or S2 sign error), noise is keyed by the frame index,
// masked pixels stay zero, and pixels whose demosaic read a clipped raw value are masked.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <numeric>
#include <optional>

#include <filesystem>

#include "render/pipeline.h"
#include "render/renderer.h"
#include "render/sensor_stage.h"
#include "scene/scene_source.h"
#include "sky/units.h"
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

namespace {

// The test's own percentile: sorted, then linear between the ranks around p/100·(n − 1).
double percentile_sorted(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double rank = p / 100 * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(rank);
  const double hi = lo + 1 < v.size() ? v[lo + 1] : v[lo];
  return v[lo] + (rank - static_cast<double>(lo)) * (hi - v[lo]);
}

scene::SensorSpec clean_auto(int w, int h) {
  scene::SensorSpec s = sensor(w, h);
  s.dofp.shot_noise = false;
  s.dofp.read_noise_e = 0;
  s.dofp.dark_current_e_s = 0;
  s.dofp.gain_dn_per_e = 1;
  s.dofp.full_well_e = 20000;
  s.dofp.electrons_per_radiance_s = 1e6;
  s.auto_exposure = camera::AutoExposure{};  // 99.5th percentile at 80 %
  return s;
}

const char* kClearSky = R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336
[time]
instants = ["2022-09-23T07:00:00Z", "2022-09-23T10:30:00Z", "2022-09-23T15:00:00Z"]
[camera]
lens_preset = "fujinon_fe185c057ha1"
binning = 16
[sensor]
preset = "sony_imx250mzr"
)";

}  // namespace

TEST_CASE("auto exposure: the sky's percentile of S0 lands at the target share of the full well", "[sensor][exposure]") {
  const int w = 40, h = 30;
  scene::SensorSpec s = clean_auto(w, h);
  stack::Frame f = uniform_frame(w, h, 0, 0, 0);
  std::vector<std::uint8_t> sky(static_cast<std::size_t>(w * h), 1);
  std::vector<double> seen;  // S0 of the pixels the meter should read
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto i = static_cast<std::size_t>(y * w + x);
      float v = 0.1f + 0.9f * static_cast<float>((i * 7919) % 1000) / 1000.0f;  // unpolarized
      if (y == 0) {
        f.channel("mask")[i] = 0;  // occluded, and bright: the meter must not read it
        v = 100;
      } else if (y >= h - 3) {
        sky[i] = 0;  // the ground, bright too
        v = 50;
      } else {
        seen.push_back(v);
      }
      f.channel("S0.Y")[i] = v;
    }
  const double p = percentile_sorted(seen, 99.5);
  const stack::Frame original = f;
  const std::size_t before = render::frames_metered();
  render::apply_sensor(s, {"Y"}, 0, f, /*keep_raw=*/true, sky);
  CHECK(render::frames_metered() == before + 1);
  REQUIRE(f.exposure_us);
  const double t_s = *f.exposure_us * 1e-6;
  CHECK(t_s == Approx(0.8 * 20000 / (1e6 * p)).epsilon(1e-6));
  // From the raw mosaic back: each polarizer passes half the unpolarized S0, 1 DN per electron,
  // so a pixel's S0 in electrons is 2·DN, rounded by the ADC to ±1 e-.
  std::vector<double> electrons;
  const std::vector<float>& raw = f.channel("raw");
  for (int y = 1; y < h - 3; ++y)
    for (int x = 0; x < w; ++x) electrons.push_back(2.0 * double{raw[static_cast<std::size_t>(y * w + x)]});
  CHECK(percentile_sorted(electrons, 99.5) == Approx(0.8 * 20000).margin(2.0));

  // Steps: the exposure is a whole number of them, at or below the exact one, by less than one.
  s.auto_exposure->step_us = 250;
  stack::Frame g = original;
  render::apply_sensor(s, {"Y"}, 0, g, false, sky);
  REQUIRE(g.exposure_us);
  CHECK(std::fmod(*g.exposure_us, 250.0) == Approx(0).margin(1e-9));
  CHECK(*g.exposure_us <= t_s * 1e6);
  CHECK(*g.exposure_us > t_s * 1e6 - 250);
}

TEST_CASE("auto exposure on a colour sensor reads each pixel in its own band, with its response", "[sensor][exposure]") {
  const int w = 16, h = 16;
  scene::SensorSpec s = clean_auto(w, h);
  s.dofp.color_filter = camera::ColorFilter::rggb_blocks;
  s.dofp.band_response = {1, 0.2, 1};
  stack::Frame f;
  f.width = w;
  f.height = h;
  const auto n = static_cast<std::size_t>(w * h);
  // G is 3× brighter than R and B, but its pixels respond at 0.2: they read 0.6, R and B 1.
  for (const auto& [b, v] : {std::pair{"R", 1.0f}, {"G", 3.0f}, {"B", 1.0f}}) {
    f.channels[std::string("S0.") + b] = std::vector<float>(n, v);
    f.channels[std::string("S1.") + b] = std::vector<float>(n, 0);
    f.channels[std::string("S2.") + b] = std::vector<float>(n, 0);
  }
  f.channels["mask"] = std::vector<float>(n, 1);
  render::apply_sensor(s, {"R", "G", "B"}, 0, f);
  REQUIRE(f.exposure_us);
  CHECK(*f.exposure_us == Approx(0.8 * 20000 / (1e6 * 1.0) * 1e6));
}

TEST_CASE("a fixed exposure is the default: no meter, the frame says the scene's exposure", "[sensor][exposure]") {
  const scene::SensorSpec s = sensor(32, 32);
  stack::Frame f = uniform_frame(32, 32, 1.0f, 0.3f, 0.4f);
  const std::size_t before = render::frames_metered();
  render::apply_sensor(s, {"Y"}, 0, f);
  CHECK(render::frames_metered() == before);  // pay for what the scene asks for
  REQUIRE(f.exposure_us);
  CHECK(*f.exposure_us == 1000);
}

TEST_CASE("the meter's sky: above the horizon, inside the image circle", "[sensor][exposure]") {
  // A 185° fisheye looking at the horizon (tilt 90°): half of the circle sees the sky, the other
  // half the ground, the corners nothing.
  std::string text = kClearSky;
  const scene::Scene sc = scene::parse_scene(text, "up.toml");
  text.replace(text.find("binning = 16\n"), 13, "binning = 16\ntilt_deg = 90\n");
  const auto cam = scene::build_camera(scene::parse_scene(text, "tilted.toml").camera);
  const std::vector<std::uint8_t> sky = render::sky_pixels(*cam);
  const int w = cam->width(), h = cam->height();
  REQUIRE(sky.size() == static_cast<std::size_t>(w * h));
  const int above = sky[static_cast<std::size_t>(h / 4 * w + w / 2)], below = sky[static_cast<std::size_t>(3 * h / 4 * w + w / 2)];
  CHECK(above + below == 1);  // one sees the sky, the other the ground
  CHECK(sky[0] == 0);
  const auto zenith = scene::build_camera(sc.camera);
  const std::vector<std::uint8_t> up = render::sky_pixels(*zenith);
  CHECK(up[static_cast<std::size_t>(h / 2 * w + w / 2)] == 1);
  CHECK(std::count(up.begin(), up.end(), 1) > std::count(sky.begin(), sky.end(), 1));
}

TEST_CASE("an auto-exposed clear sky: no pixel clipped, each frame's exposure in its header", "[sensor][exposure]") {
  const scene::Scene sc = scene::parse_scene(std::string(kClearSky) + "exposure = \"auto\"\n", "auto.toml");
  const std::string path = (std::filesystem::temp_directory_path() / "skypol-sensor-auto.exr").string();
  const std::size_t before = render::frames_metered();
  render::render_scene(sc, path);
  CHECK(render::frames_metered() == before + 3);
  const stack::Stack st = stack::read_stack(path);
  CHECK_THAT(stack::describe_stack(path), Catch::Contains("exposure: ") && Catch::Contains(" us (per frame: skypol:exposureUs)"));
  std::filesystem::remove(path);
  REQUIRE(st.frames.size() == 3);
  // The header's exposure is the meter's on the ideal frame, recomputed here.
  render::RenderOptions ro;
  const auto cam = scene::build_camera(sc.camera);
  const render::Renderer renderer(cam, ro);
  const auto sky = scene::build_sky(sc.sky);
  const std::vector<std::uint8_t> region = render::sky_pixels(*cam);
  for (std::size_t i = 0; i < 3; ++i) {
    const stack::Frame& f = st.frames[i];
    INFO("frame " << i);
    REQUIRE(f.exposure_us);
    stack::Frame ideal = renderer.render(*sky, f.truth.sun);
    CHECK(*f.exposure_us == render::meter_exposure_us(*sc.sensor, {"Y"}, ideal, region));
    // Nothing clipped at 80 % of the well, noise and all.
    const std::vector<float>& clipped = f.channel("clipped");
    CHECK(std::count(clipped.begin(), clipped.end(), 1.0f) == 0);
  }
  // Each frame is metered on its own sky (the grey Rayleigh sky's brightest part changes little).
  CHECK(*st.frames[1].exposure_us != *st.frames[0].exposure_us);

  // The fixed exposure's stack says it too, and meters nothing.
  const scene::Scene fixed = scene::parse_scene(std::string(kClearSky) + "exposure_us = 640\n", "fixed.toml");
  const std::size_t again = render::frames_metered();
  render::render_scene(fixed, path);
  CHECK(render::frames_metered() == again);
  const stack::Stack fs = stack::read_stack(path);
  CHECK_THAT(stack::describe_stack(path), Catch::Contains("exposure: 640 us, every frame"));
  std::filesystem::remove(path);
  for (const stack::Frame& f : fs.frames) CHECK(f.exposure_us == std::optional<double>(640));
}

TEST_CASE("a stack's exposures round-trip through its headers, and only a sensor's stack has them", "[sensor][exposure]") {
  const std::string path = (std::filesystem::temp_directory_path() / "skypol-exposure-roundtrip.exr").string();
  std::vector<scene::Truth> truths(3);
  for (std::size_t i = 0; i < 3; ++i) truths[i].time = sky::Instant{1.6639e9 + 60.0 * static_cast<double>(i)};
  stack::StackHeader header;
  header.camera_description = "model = \"equidistant\"\nfx = 2\nwidth = 4\nheight = 3\n";
  header.sky_model = "rayleigh";
  header.exposures = true;
  const double us[3] = {1234.5678901234, 0.001, 9.87654321e6};  // exact doubles, any magnitude
  stack::write_stack(path, truths, {"mask"}, 4, 3, header, {}, [&](std::size_t i) {
    stack::Frame f = uniform_frame(4, 3, 0, 0, 0);
    f.exposure_us = us[i];
    return f;
  });
  stack::Stack st = stack::read_stack(path);
  REQUIRE(st.frames.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) CHECK(st.frames[i].exposure_us == std::optional<double>(us[i]));
  // Headers of many kB each (a long scene text), over several of the blocks the writer reads them
  // back in: every part still gets its own value.
  {
    stack::StackHeader big = header;
    big.scene_text = std::string(9000, '#');
    std::vector<scene::Truth> many(40);
    for (std::size_t i = 0; i < many.size(); ++i) many[i].time = sky::Instant{1.6639e9 + 60.0 * static_cast<double>(i)};
    stack::write_stack(path, many, {"mask"}, 4, 3, big, {}, [&](std::size_t i) {
      stack::Frame f = uniform_frame(4, 3, 0, 0, 0);
      f.exposure_us = 100.0 + static_cast<double>(i);
      return f;
    });
    const stack::Stack back = stack::read_stack(path);
    REQUIRE(back.frames.size() == 40);
    for (std::size_t i = 0; i < 40; ++i) CHECK(back.frames[i].exposure_us == std::optional<double>(100.0 + static_cast<double>(i)));
  }
  // A frame without an exposure in a stack whose parts carry one: refused, nothing written.
  std::filesystem::remove(path);
  CHECK_THROWS(stack::write_stack(path, truths, {"mask"}, 4, 3, header, {}, [&](std::size_t i) {
    stack::Frame f = uniform_frame(4, 3, 0, 0, 0);
    if (i != 1) f.exposure_us = us[i];
    return f;
  }));
  CHECK_FALSE(std::filesystem::exists(path));
  // Without a sensor: no attribute, no exposure read back.
  header.exposures = false;
  stack::write_stack(path, truths, {"mask"}, 4, 3, header, {}, [&](std::size_t) { return uniform_frame(4, 3, 0, 0, 0); });
  st = stack::read_stack(path);
  std::filesystem::remove(path);
  for (const stack::Frame& f : st.frames) CHECK_FALSE(f.exposure_us);
}

namespace {

// FNV-1a, 64 bits, over the bytes of the values (little-endian, as on every machine skypol builds for).
template <class T>
std::uint64_t fnv1a(const std::vector<T>& values, std::uint64_t h) {
  for (const T v : values) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    for (const unsigned char b : bytes) h = (h ^ b) * 0x100000001b3ULL;
  }
  return h;
}

}  // namespace

TEST_CASE("a fixed exposure renders the shipped sensor scene as it did before auto exposure", "[sensor][exposure]") {
  // The checksums of skypole-marseille-dofp.toml at binning 16 (23 frames, float), computed with
  // OpenImageIO and NumPy: its raw mosaic (DN) from a render by a build without auto exposure,
  // and S0.G with the colour sensor's mask eroded by its demosaic's reach (3 pixels: the ring
  // between held Stokes, which mixes in darkness, is zeros). Any change to the sensor's pixels,
  // or to what it is fed, shows here.
  const std::string scene_file = std::string(SKYPOL_SOURCE_DIR) + "/scenes/skypole-marseille-dofp.toml";
  const scene::Scene sc = scene::load_scene(
      scene_file, {scene::parse_override("camera.binning=16"), scene::parse_override("output.pixel_type=\"float\""),
                   scene::parse_override("output.channels=[\"S0\", \"DoLP\", \"mask\", \"raw\"]")});
  REQUIRE(sc.sensor);
  REQUIRE_FALSE(sc.sensor->auto_exposure);
  const std::string path = (std::filesystem::temp_directory_path() / "skypol-sensor-fixed-dofp.exr").string();
  render::render_scene(sc, path);
  const stack::Stack st = stack::read_stack(path, {"raw", "S0.G"});
  std::filesystem::remove(path);
  REQUIRE(st.frames.size() == 23);
  std::uint64_t raw = 0xcbf29ce484222325ULL, s0 = raw;
  for (const stack::Frame& f : st.frames) {
    const std::vector<float>& r = f.channel("raw");
    raw = fnv1a(std::vector<std::uint16_t>(r.begin(), r.end()), raw);
    s0 = fnv1a(f.channel("S0.G"), s0);
    CHECK(f.exposure_us == std::optional<double>(1000));  // the preset's
  }
  CHECK(raw == 0x1afa5b9d4c5d709aULL);
  CHECK(s0 == 0x23c0c881e7b02119ULL);
}

TEST_CASE("a vrte sky through an auto-exposed sensor needs no hand scaling", "[sensor][exposure][vrte]") {
  // The sky's S0 is I/F (≈ 0.01–1 sr⁻¹), 30–50× darker than the grey models' unit: the meter
  // finds the exposure that a fixed one would have to be scaled by hand to.
  const std::string automatic = std::string(kClearSky) + "exposure = \"auto\"\n";
  const scene::Scene vrte = scene::parse_scene(automatic + "[sky]\nmodel = \"vrte\"\nstreams = 8\ngrid = 17\n", "vrte.toml");
  const scene::Scene rayleigh = scene::parse_scene(automatic, "rayleigh.toml");
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "skypol-sensor-vrte";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "vrte.exr").string();
  render::render_scene(vrte, path, {}, dir / "tables");
  const stack::Stack v = stack::read_stack(path);
  render::render_scene(rayleigh, path);
  const stack::Stack r = stack::read_stack(path);
  std::filesystem::remove_all(dir);
  REQUIRE(v.frames.size() == 3);
  const auto cam = scene::build_camera(vrte.camera);
  for (std::size_t i = 0; i < 3; ++i) {
    INFO("frame " << i);
    REQUIRE(v.frames[i].exposure_us);
    const double ratio = *v.frames[i].exposure_us / *r.frames[i].exposure_us;
    CHECK(ratio > 5);
    CHECK(ratio < 200);
    const std::vector<float>& mask = v.frames[i].channel("mask");
    const std::vector<float>& clipped = v.frames[i].channel("clipped");
    const auto sky = std::count_if(mask.begin(), mask.end(), [](float m) { return m > 0; });
    const auto lost = std::count(clipped.begin(), clipped.end(), 1.0f);
    // Unlike Rayleigh's, this sky has an aureole: next to the sun it is more than 2.5× its 99.5th
    // percentile, the most a polarizer at 80 % can take, and clips there as a camera's would.
    // Nowhere else.
    double farthest_deg = 0;
    for (int y = 0; y < v.frames[i].height; ++y)
      for (int x = 0; x < v.frames[i].width; ++x) {
        if (clipped[static_cast<std::size_t>(y * v.frames[i].width + x)] == 0.0f) continue;
        const auto ray = cam->ray(Eigen::Vector2d(x, y));
        REQUIRE(ray);
        farthest_deg = std::max(farthest_deg, std::acos(std::clamp(ray->d.dot(v.frames[i].truth.sun.direction), -1.0, 1.0)) / kRadPerDeg);
      }
    INFO(ratio << "x the Rayleigh exposure, " << lost << " of " << sky << " sky pixels clipped, the farthest "
               << farthest_deg << " deg from the sun");
    CHECK(lost < sky / 200);  // fewer than the 0.5 % above the percentile
    CHECK(farthest_deg < 8);
  }
}

TEST_CASE("a frame says what its AoLP assumes of the polarizers, and its header keeps it", "[sensor]") {
  using stack::PolarizerAngles;
  // The sensor stage: calibrated where the demosaic's angles are the polarizers' own.
  scene::SensorSpec s = sensor(8, 8);
  stack::Frame f = uniform_frame(8, 8, 1.0f, 0.3f, 0.4f);
  render::apply_sensor(s, {"Y"}, 0, f);
  CHECK(f.polarizer_angles == PolarizerAngles::calibrated);  // ideal polarizers, nominal demosaic
  s.dofp.angle_error_deg = {0.5, 0, 0, 0};
  f = uniform_frame(8, 8, 1.0f, 0.3f, 0.4f);
  render::apply_sensor(s, {"Y"}, 0, f);
  CHECK(f.polarizer_angles == PolarizerAngles::nominal);
  CHECK(render::polarizer_angles(s) == PolarizerAngles::nominal);
  s.demosaic = camera::Demosaic::calibrated;
  CHECK(render::polarizer_angles(s) == PolarizerAngles::calibrated);

  // The header: skypol:polarizerAngles on every part, absent without a sensor; a value that is
  // neither name is refused, naming the attribute.
  const std::string path = (std::filesystem::temp_directory_path() / "skypol-polarizer-angles.exr").string();
  std::vector<scene::Truth> truths(2);
  for (std::size_t i = 0; i < 2; ++i) truths[i].time = sky::Instant{1.6639e9 + 60.0 * static_cast<double>(i)};
  stack::StackHeader header;
  header.camera_description = "model = \"equidistant\"\nfx = 2\nwidth = 4\nheight = 3\n";
  header.sky_model = "rayleigh";
  const auto written = [&](const stack::StackHeader& h) {
    stack::write_stack(path, truths, {"mask"}, 4, 3, h, {}, [&](std::size_t) { return uniform_frame(4, 3, 0, 0, 0); });
    const stack::Stack st = stack::read_stack(path);
    std::filesystem::remove(path);
    REQUIRE(st.frames.size() == 2);
    CHECK(st.frames[0].polarizer_angles == st.frames[1].polarizer_angles);
    return st.frames[1].polarizer_angles;
  };
  for (const PolarizerAngles a : {PolarizerAngles::none, PolarizerAngles::calibrated, PolarizerAngles::nominal}) {
    header.polarizer_angles = a;
    CHECK(written(header) == a);
  }
  header.polarizer_angles = PolarizerAngles::none;
  header.attributes = {{"skypol:polarizerAngles", "sideways"}};
  stack::write_stack(path, truths, {"mask"}, 4, 3, header, {}, [&](std::size_t) { return uniform_frame(4, 3, 0, 0, 0); });
  CHECK_THROWS_WITH(stack::read_stack(path), Catch::Contains("skypol:polarizerAngles") && Catch::Contains("sideways"));
  std::filesystem::remove(path);
}
