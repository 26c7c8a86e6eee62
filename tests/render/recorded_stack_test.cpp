// render/recorded_stack.h: stacks recorded in memory carry the renderer's truth, and a noise-free
// DoFP sensor gives back the renderer's DoLP and AoLP (through the mosaic and the demosaic).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

#include "camera/intrinsics.h"
#include "camera/radial_lens.h"
#include "camera/presets.h"
#include "render/recorded_stack.h"
#include "render/sensor_stage.h"
#include "sky/units.h"

using namespace skypol;

namespace {
render::RecordingSetup setup() {
  render::RecordingSetup s;
  s.site = {43.28699, 5.40336, 0};
  const double tmax = rad_from_deg(92.5);
  camera::Intrinsics k;
  k.width = k.height = 96;
  k.fx = k.fy = 48 / tmax;
  k.cx = k.cy = 47.5;
  s.lens = std::make_shared<camera::RadialLens>(camera::Mapping::equidistant, k, tmax);
  s.heading_deg = 40;
  s.sky.max_dolp = 0.7;
  return s;
}

// `s` without noise, with a deep well and a 16-bit ADC: ≈ 30000 DN at radiance 1, so that
// quantization is ≪ 1e-3.
camera::DofpSensor noise_free(camera::DofpSensor s) {
  s.shot_noise = false;
  s.read_noise_e = 0;
  s.dark_current_e_s = 0;
  s.adc_bits = 16;
  s.full_well_e = 1e9;
  s.gain_dn_per_e = 1;
  s.electrons_per_radiance_s = 3e7;
  return s;
}
}  // namespace

TEST_CASE("recorded frames carry the truth and the channels the estimators read", "[render][recorded_stack]") {
  const auto times = {sky::parse_iso8601("2022-09-23T09:00:00Z"), sky::parse_iso8601("2022-09-23T10:00:00Z")};
  const stack::Stack st = render::record_stack(setup(), times);
  REQUIRE(st.frames.size() == 2);
  for (const stack::Frame& f : st.frames) {
    CHECK(f.truth.heading_deg == 40);
    CHECK(f.truth.site.latitude_deg == 43.28699);
    REQUIRE(f.truth.pole_pixel.has_value());
    for (const char* c : {"S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y", "mask"}) CHECK(f.has(c));
  }
  // The sun's elevation rises by 7° between 09:00 and 10:00 UTC on the paper's day.
  const double rise = deg_from_rad(st.frames[1].truth.sun.elevation - st.frames[0].truth.sun.elevation);
  CHECK(rise == Approx(7.0).margin(0.5));
  const render::RecordingSetup no_lens;
  CHECK_THROWS_AS(render::record_stack(no_lens, times), std::invalid_argument);
  render::RecordingSetup no_band = setup();
  no_band.bands.clear();
  CHECK_THROWS_AS(render::record_stack(no_band, times), std::invalid_argument);
}

TEST_CASE("a noise-free DoFP sensor returns the renderer's DoLP and AoLP", "[render][recorded_stack]") {
  const stack::Stack ideal = render::record_stack(setup(), {sky::parse_iso8601("2022-09-23T11:00:00Z")});
  const stack::Stack got = render::through_sensor(ideal, noise_free(camera::DofpSensor{}));
  const auto& d0 = ideal.frames[0].channel("DoLP.Y");
  const auto& a0 = ideal.frames[0].channel("AoLP.Y");
  const auto& d1 = got.frames[0].channel("DoLP.Y");
  const auto& a1 = got.frames[0].channel("AoLP.Y");
  const auto& m1 = got.frames[0].channel("mask");
  const auto& m0 = ideal.frames[0].channel("mask");
  int used = 0, eroded = 0;
  double worst_dolp = 0, worst_aolp = 0;
  for (std::size_t i = 0; i < d0.size(); ++i) {
    if (m0[i] > 0 && m1[i] == 0) ++eroded;
    if (m1[i] == 0) continue;
    CHECK(m0[i] > 0);  // the eroded mask lies inside the renderer's
    ++used;
    // The bilinear demosaic interpolates each polarizer over a 2-pixel lattice: on this coarse grid
    // the sky's curvature across 2 pixels bounds the agreement.
    worst_dolp = std::max(worst_dolp, std::abs(static_cast<double>(d1[i] - d0[i])));
    const double da = std::remainder(static_cast<double>(a1[i] - a0[i]), std::numbers::pi);
    if (d0[i] > 0.05f) worst_aolp = std::max(worst_aolp, std::abs(da));
  }
  CHECK(used > 6000);
  CHECK(eroded > 100);  // the ring next to the image circle's edge
  CHECK(worst_dolp < 0.03);
  CHECK(worst_aolp < rad_from_deg(3));
  CHECK_FALSE(got.frames[0].has("S0.Y"));
}

TEST_CASE("through_sensor auto-exposes each frame when asked, on the sky above its camera's horizon", "[render][recorded_stack][exposure]") {
  const stack::Stack ideal = render::record_stack(
      setup(), {sky::parse_iso8601("2022-09-23T07:00:00Z"), sky::parse_iso8601("2022-09-23T11:00:00Z")});
  camera::DofpSensor s;
  s.exposure_us = 700;
  const stack::Stack fixed = render::through_sensor(ideal, s);
  for (const stack::Frame& f : fixed.frames) CHECK(f.exposure_us == std::optional<double>(700));
  const stack::Stack metered = render::through_sensor(ideal, s, camera::AutoExposure{});
  // What the sensor stage's meter reads on the ideal frames: the sky the 92.5° lens sees above the
  // horizon (its outer 2.5° look at the ground).
  scene::SensorSpec spec;
  spec.dofp = s;
  spec.dofp.width = spec.dofp.height = 96;
  spec.auto_exposure = camera::AutoExposure{};
  const std::vector<std::uint8_t> sky = render::sky_pixels(*ideal.camera);
  CHECK(std::count(sky.begin(), sky.end(), 1) <
        std::count_if(ideal.frames[0].channel("mask").begin(), ideal.frames[0].channel("mask").end(), [](float m) { return m > 0; }));
  for (std::size_t i = 0; i < 2; ++i) {
    REQUIRE(metered.frames[i].exposure_us);
    CHECK(*metered.frames[i].exposure_us == render::meter_exposure_us(spec, {"Y"}, ideal.frames[i], sky));
    CHECK(*metered.frames[i].exposure_us != 700);
  }
  camera::AutoExposure bad;
  bad.target = 2;
  CHECK_THROWS_AS(render::through_sensor(ideal, s, bad), std::invalid_argument);
}

TEST_CASE("a colour DoFP sensor records R, G and B, each near the renderer's", "[render][recorded_stack]") {
  render::RecordingSetup rgb = setup();
  rgb.bands = {"R", "G", "B"};
  const stack::Stack ideal = render::record_stack(rgb, {sky::parse_iso8601("2022-09-23T11:00:00Z")});
  for (const char* c : {"S0.R", "S0.G", "S0.B", "DoLP.R", "DoLP.G", "DoLP.B"}) CHECK(ideal.frames[0].has(c));
  const camera::DofpSensor s = noise_free(camera::sensor_preset("lucid_phx050s_qc").dofp);
  const stack::Stack got = render::through_sensor(ideal, s);
  REQUIRE(got.bands == rgb.bands);
  const auto& mask = got.frames[0].channel("mask");
  for (const char* b : {"R", "G", "B"}) {
    INFO(b);
    const auto& d0 = ideal.frames[0].channel(std::string("DoLP.") + b);
    const auto& d1 = got.frames[0].channel(std::string("DoLP.") + b);
    double worst = 0;
    int used = 0;
    for (std::size_t i = 0; i < d0.size(); ++i)
      if (mask[i] > 0) {
        ++used;
        worst = std::max(worst, std::abs(static_cast<double>(d1[i] - d0[i])));
      }
    CHECK(used > 5000);
    // Each colour's polarizer block repeats every 4 pixels (RGGB over 2×2 blocks): the demosaic
    // interpolates over twice the mono lattice, so the sky's curvature bounds it (2²) 4 times more
    // loosely than the mono case's 0.03. The mask is eroded by 3 pixels, the colour demosaic's reach:
    // eroded by mono's 1, the ring next to the circle's edge, which mixes in darkness, is 0.2–0.33 off.
    CHECK(worst < 0.12);
  }
  // A mono sensor cannot take three bands, nor a colour one a single band.
  CHECK_THROWS_AS(render::through_sensor(ideal, camera::DofpSensor{}), std::invalid_argument);
  const stack::Stack mono = render::record_stack(setup(), {sky::parse_iso8601("2022-09-23T11:00:00Z")});
  CHECK_THROWS_AS(render::through_sensor(mono, s), std::invalid_argument);
}
