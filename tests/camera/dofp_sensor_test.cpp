// DoFP sensor: Malus' law per mosaic pixel, the IMX250MZR layout, noise statistics, saturation,
// reproducibility per seed, and the bilinear demosaic on known patterns.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <tbb/global_control.h>

#include "camera/dofp_sensor.h"
#include "sky/units.h"

using namespace skypol::camera;
using skypol::kRadPerDeg;

namespace {

// Noise-free sensor: 1 DN per electron, 4000 e per unit radiance (exposure 1 ms).
DofpSensor clean(int w = 64, int h = 48) {
  DofpSensor s;
  s.width = w;
  s.height = h;
  s.exposure_us = 1000;
  s.electrons_per_radiance_s = 4e6;
  s.gain_dn_per_e = 1;
  s.read_noise_e = 0;
  s.dark_current_e_s = 0;
  s.shot_noise = false;
  s.full_well_e = 1e9;
  s.adc_bits = 16;
  return s;
}

struct Field {
  std::vector<float> s0, s1, s2;
};
Field uniform(const DofpSensor& s, float s0, float s1, float s2) {
  const auto n = static_cast<std::size_t>(s.width * s.height);
  return {std::vector<float>(n, s0), std::vector<float>(n, s1), std::vector<float>(n, s2)};
}

// Mean and variance of the raw values of one mosaic position.
std::pair<double, double> stats(const std::vector<std::uint16_t>& raw, const DofpSensor& s, int pos) {
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int r = pos >> 1; r < s.height; r += 2)
    for (int c = pos & 1; c < s.width; c += 2) {
      const double v = raw[static_cast<std::size_t>(r * s.width + c)];
      sum += v;
      sum2 += v * v;
      ++n;
    }
  const double mean = sum / n;
  return {mean, sum2 / n - mean * mean};
}
}  // namespace

TEST_CASE("Malus' law behind each micro-polarizer, with extinction ratio and angle error", "[sensor]") {
  DofpSensor s = clean();
  // IMX250MZR layout: (0,0) 90°, (0,1) 45°, (1,0) 135°, (1,1) 0°. Light polarized at 0°, S = (1, 1, 0).
  CHECK(polarizer_radiance(s, 0, 0, 1, 1, 0) == Approx(0).margin(1e-8));
  CHECK(polarizer_radiance(s, 0, 1, 1, 1, 0) == Approx(0.5));
  CHECK(polarizer_radiance(s, 1, 0, 1, 1, 0) == Approx(0.5));
  CHECK(polarizer_radiance(s, 1, 1, 1, 1, 0) == Approx(1));
  CHECK(polarizer_radiance(s, 2, 5, 1, 0, 1) == Approx(1));  // 45° light on a 45° pixel (even row, odd col)
  // Unpolarized light: half of S0 everywhere.
  CHECK(polarizer_radiance(s, 2, 2, 2, 0, 0) == Approx(1));
  // Extinction ratio 100: crossed polarizer passes S0/ER.
  s.extinction_ratio = 100;
  CHECK(polarizer_radiance(s, 1, 1, 1, -1, 0) == Approx(0.01));
  // A 0° pixel rotated by +5°: ½(1 + cos 10°) of 0°-polarized light.
  s.extinction_ratio = 1e12;
  s.angle_error_deg = {0, 0, 0, 5};
  CHECK(polarizer_radiance(s, 1, 1, 1, 1, 0) == Approx(0.5 * (1 + std::cos(10 * kRadPerDeg))));
}

TEST_CASE("noise-free uniform field: raw values and demosaic recover Stokes to quantization", "[sensor]") {
  const DofpSensor s = clean();
  const Field f = uniform(s, 1.0f, 0.3f, -0.2f);
  const auto raw = simulate_raw(s, f.s0, f.s1, f.s2, 0);
  // 0° pixel (1,1): ½(1 + 0.3)·4000 = 2600 DN; 90° pixel (0,0): ½(1 − 0.3)·4000 = 1400 DN.
  CHECK(raw[static_cast<std::size_t>(1 * s.width + 1)] == 2600);
  CHECK(raw[0] == 1400);
  CHECK(raw[1] == 1600);  // 45°: ½(1 − 0.2)·4000
  const StokesPlanes st = demosaic_bilinear(s, raw);
  for (std::size_t i = 0; i < st.s0.size(); ++i) {
    REQUIRE(st.s0[i] == Approx(1.0).margin(3e-4));
    REQUIRE(st.s1[i] == Approx(0.3).margin(3e-4));
    REQUIRE(st.s2[i] == Approx(-0.2).margin(3e-4));
  }
}

TEST_CASE("bilinear demosaic is exact on a linear ramp away from the border", "[sensor]") {
  const DofpSensor s = clean(40, 30);
  Field f = uniform(s, 0, 0, 0);
  // S0 = 0.5 + 0.01·col + 0.005·row, S1 = 0.2·S0 (DoLP 0.2 at 0°), S2 = −0.004·col.
  for (int r = 0; r < s.height; ++r)
    for (int c = 0; c < s.width; ++c) {
      const auto i = static_cast<std::size_t>(r * s.width + c);
      f.s0[i] = static_cast<float>(0.5 + 0.01 * c + 0.005 * r);
      f.s1[i] = 0.2f * f.s0[i];
      f.s2[i] = static_cast<float>(-0.004 * c);
    }
  const StokesPlanes st = demosaic_bilinear(s, simulate_raw(s, f.s0, f.s1, f.s2, 0));
  for (int r = 1; r < s.height - 1; ++r)
    for (int c = 1; c < s.width - 1; ++c) {
      const auto i = static_cast<std::size_t>(r * s.width + c);
      REQUIRE(st.s0[i] == Approx(f.s0[i]).margin(3e-4));
      REQUIRE(st.s1[i] == Approx(f.s1[i]).margin(3e-4));
      REQUIRE(st.s2[i] == Approx(f.s2[i]).margin(3e-4));
    }
}

TEST_CASE("uncalibrated demosaic shows the extinction ratio: DoLP 1 reads (ER−1)/(ER+1)", "[sensor]") {
  DofpSensor s = clean();
  s.extinction_ratio = 100;
  const Field f = uniform(s, 1, 0, 1);  // fully polarized at 45°
  const StokesPlanes st = demosaic_bilinear(s, simulate_raw(s, f.s0, f.s1, f.s2, 0));
  const std::size_t i = 10 * 64 + 10;
  const double dolp = std::hypot(st.s1[i], st.s2[i]) / st.s0[i];
  CHECK(dolp == Approx(99.0 / 101.0).margin(5e-4));
}

TEST_CASE("photon transfer: mean g·λ and variance g²(λ + σr²) + 1/12, Poisson and Gaussian regimes", "[sensor]") {
  for (double lambda : {20.0, 1000.0}) {
    DofpSensor s = clean(256, 256);
    s.shot_noise = true;
    s.read_noise_e = 2;
    s.seed = 7;
    // Unpolarized S0 = 2λ/4000 → λ electrons behind every polarizer.
    const Field f = uniform(s, static_cast<float>(2 * lambda / 4000), 0, 0);
    const auto raw = simulate_raw(s, f.s0, f.s1, f.s2, 3);
    for (int pos = 0; pos < 4; ++pos) {
      const auto [mean, var] = stats(raw, s, pos);
      INFO("lambda " << lambda << " pos " << pos << " mean " << mean << " var " << var);
      CHECK(mean == Approx(lambda).epsilon(0.005));
      CHECK(var == Approx(lambda + 4 + 1.0 / 12).epsilon(0.05));
    }
  }
}

TEST_CASE("dark current, full well and ADC clipping", "[sensor]") {
  DofpSensor s = clean(32, 32);
  s.exposure_us = 1e6;  // 1 s
  s.dark_current_e_s = 500;
  s.electrons_per_radiance_s = 1;
  const Field dark = uniform(s, 0, 0, 0);
  const auto raw = simulate_raw(s, dark.s0, dark.s1, dark.s2, 0);
  CHECK(raw[5] == 500);
  // Full well 10500 e at 0.39 DN/e is 4095 DN = 12-bit full scale.
  s = clean(32, 32);
  s.full_well_e = 10500;
  s.gain_dn_per_e = 0.39;
  s.adc_bits = 12;
  const Field bright = uniform(s, 1e3f, 0, 0);
  for (auto v : simulate_raw(s, bright.s0, bright.s1, bright.s2, 0)) REQUIRE(v == 4095);
  s.gain_dn_per_e = 0.2;  // saturates at the well: 2100 DN
  for (auto v : simulate_raw(s, bright.s0, bright.s1, bright.s2, 0)) REQUIRE(v == 2100);
  s.gain_dn_per_e = 1;  // saturates at the ADC: 4095 DN
  for (auto v : simulate_raw(s, bright.s0, bright.s1, bright.s2, 0)) REQUIRE(v == 4095);
  // NaN or negative input (masked pixels) reads as black, never as garbage.
  const Field nan = uniform(s, std::nanf(""), 0, 0);
  for (auto v : simulate_raw(s, nan.s0, nan.s1, nan.s2, 0)) REQUIRE(v == 0);
}

TEST_CASE("noise is reproducible per (seed, frame, pixel), whatever the order of evaluation", "[sensor]") {
  DofpSensor s = clean(50, 40);
  s.shot_noise = true;
  s.read_noise_e = 3;
  s.seed = 42;
  const Field f = uniform(s, 0.05f, 0.01f, 0);
  const auto a = simulate_raw(s, f.s0, f.s1, f.s2, 9);
  CHECK(a == simulate_raw(s, f.s0, f.s1, f.s2, 9));
  // Pixel by pixel in reverse order (as threads in any order would) gives the same frame.
  for (int r = s.height - 1; r >= 0; --r)
    for (int c = s.width - 1; c >= 0; --c) {
      const auto i = static_cast<std::size_t>(r * s.width + c);
      REQUIRE(simulate_pixel(s, r, c, f.s0[i], f.s1[i], f.s2[i], 9) == a[i]);
    }
  CHECK(a != simulate_raw(s, f.s0, f.s1, f.s2, 10));
  s.seed = 43;
  CHECK(a != simulate_raw(s, f.s0, f.s1, f.s2, 9));
}

TEST_CASE("raw frame and demosaic are the same bytes on one thread as on all", "[sensor]") {
  DofpSensor s = clean(300, 200);  // more rows than one parallel chunk holds
  s.shot_noise = true;
  s.read_noise_e = 3;
  s.seed = 7;
  const Field f = uniform(s, 0.05f, 0.01f, 0.02f);
  const auto parallel_raw = simulate_raw(s, f.s0, f.s1, f.s2, 3);
  const StokesPlanes parallel_stokes = demosaic_bilinear(s, parallel_raw, Demosaic::nominal);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  CHECK(simulate_raw(s, f.s0, f.s1, f.s2, 3) == parallel_raw);
  const StokesPlanes serial = demosaic_bilinear(s, parallel_raw, Demosaic::nominal);
  CHECK(serial.s0 == parallel_stokes.s0);
  CHECK(serial.s1 == parallel_stokes.s1);
  CHECK(serial.s2 == parallel_stokes.s2);
}

TEST_CASE("the _into forms reuse buffers full of old values and give the same frame", "[sensor]") {
  DofpSensor s = clean(40, 32);
  s.shot_noise = true;
  s.seed = 5;
  const Field f = uniform(s, 0.05f, 0.02f, -0.01f);
  const auto n = static_cast<std::size_t>(s.width * s.height);
  std::vector<std::uint16_t> raw(n, 4095);
  simulate_raw_into(s, f.s0, f.s1, f.s2, 2, raw);
  CHECK(raw == simulate_raw(s, f.s0, f.s1, f.s2, 2));
  StokesPlanes reused{std::vector<float>(n, -7.0f), std::vector<float>(n, -7.0f), std::vector<float>(n, -7.0f)};
  const float* storage = reused.s0.data();
  demosaic_bilinear_into(s, raw, Demosaic::nominal, reused);
  CHECK(reused.s0.data() == storage);  // no new allocation
  const StokesPlanes fresh = demosaic_bilinear(s, raw);
  CHECK(reused.s0 == fresh.s0);
  CHECK(reused.s1 == fresh.s1);
  CHECK(reused.s2 == fresh.s2);
}

TEST_CASE("bad sensor parameters are named", "[sensor]") {
  DofpSensor s = clean();
  s.extinction_ratio = 1;
  CHECK_THROWS_WITH(validate(s), "extinction_ratio must be > 1");
  s = clean();
  s.adc_bits = 20;
  CHECK_THROWS_WITH(validate(s), "adc_bits must be in [1, 16]");
  s = clean();
  s.exposure_us = 0;
  CHECK_THROWS_WITH(validate(s), "exposure_us must be > 0");
  s = clean();
  s.mosaic_deg = {0, 0, 90, 135};
  const Field f = uniform(s, 1, 0, 0);
  CHECK_THROWS_WITH(demosaic_bilinear(s, simulate_raw(s, f.s0, f.s1, f.s2, 0)),
                    "mosaic_deg must hold 0, 45, 90 and 135");
  std::vector<float> small(3);
  CHECK_THROWS_AS(simulate_raw(clean(), small, small, small, 0), std::invalid_argument);
}

TEST_CASE("calibrated demosaic undoes extinction ratio and angle errors", "[sensor]") {
  DofpSensor s = clean();
  s.extinction_ratio = 50;
  s.angle_error_deg = {1.5, -2, 0.7, 3};
  // Light with DoLP 0.8 at AoLP 20°: S = (1, 0.8 cos 40°, 0.8 sin 40°).
  const float s1 = static_cast<float>(0.8 * std::cos(40 * kRadPerDeg)), s2 = static_cast<float>(0.8 * std::sin(40 * kRadPerDeg));
  const Field f = uniform(s, 1, s1, s2);
  const auto raw = simulate_raw(s, f.s0, f.s1, f.s2, 0);
  const StokesPlanes cal = demosaic_bilinear(s, raw, Demosaic::calibrated);
  const StokesPlanes nom = demosaic_bilinear(s, raw);
  const std::size_t i = 20 * 64 + 30;
  CHECK(cal.s0[i] == Approx(1).margin(3e-4));
  CHECK(cal.s1[i] == Approx(s1).margin(3e-4));
  CHECK(cal.s2[i] == Approx(s2).margin(3e-4));
  // The nominal pipeline is off by the errors: its AoLP misses 20° by more than 0.1°.
  const double aolp_nom = 0.5 * std::atan2(double{nom.s2[i]}, double{nom.s1[i]}) / kRadPerDeg;
  CHECK(std::abs(aolp_nom - 20) > 0.1);
  CHECK(0.5 * std::atan2(double{cal.s2[i]}, double{cal.s1[i]}) / kRadPerDeg == Approx(20).margin(0.02));
}

TEST_CASE("colour DoFP (IMX250MYR): RGGB over polarizer blocks, per-band Stokes recovered", "[sensor]") {
  DofpSensor s = clean(64, 48);
  s.color_filter = ColorFilter::rggb_blocks;
  s.band_response = {0.8, 1.0, 0.6};
  // Block (0,0) red, (0,1) and (1,0) green, (1,1) blue; a block is 2×2 pixels.
  CHECK(band_of_pixel(s, 0, 0) == 0);
  CHECK(band_of_pixel(s, 1, 1) == 0);
  CHECK(band_of_pixel(s, 0, 2) == 1);
  CHECK(band_of_pixel(s, 2, 1) == 1);
  CHECK(band_of_pixel(s, 3, 3) == 2);
  CHECK(band_of_pixel(s, 4, 4) == 0);
  // Different Stokes per band, linear in the column (bilinear on 4-pixel lattices stays exact).
  const auto n = static_cast<std::size_t>(s.width * s.height);
  std::array<std::vector<float>, 9> planes;
  for (auto& v : planes) v.resize(n);
  for (int r = 0; r < s.height; ++r)
    for (int c = 0; c < s.width; ++c) {
      const auto i = static_cast<std::size_t>(r * s.width + c);
      for (std::size_t b = 0; b < 3; ++b) {
        planes[3 * b][i] = static_cast<float>(0.5 + 0.2 * static_cast<double>(b) + 0.004 * c);
        planes[3 * b + 1][i] = static_cast<float>(0.1 * static_cast<double>(b + 1) - 0.001 * r);
        planes[3 * b + 2][i] = static_cast<float>(-0.05 * static_cast<double>(b));
      }
    }
  std::array<BandStokes, 3> rgb;
  for (std::size_t b = 0; b < 3; ++b) rgb[b] = {planes[3 * b], planes[3 * b + 1], planes[3 * b + 2]};
  const auto raw = simulate_raw_color(s, rgb, 0);
  // Pixel (1,1): red block, 0° polarizer: ½(S0 + S1)·0.8·4000 DN.
  const auto i11 = static_cast<std::size_t>(s.width + 1);
  CHECK(raw[i11] == std::lround(0.5 * (double{planes[0][i11]} + double{planes[1][i11]}) * 0.8 * 4000));
  const auto st = demosaic_color_bilinear(s, raw);
  for (int r = 4; r < s.height - 4; ++r)
    for (int c = 4; c < s.width - 4; ++c) {
      const auto i = static_cast<std::size_t>(r * s.width + c);
      for (std::size_t b = 0; b < 3; ++b) {
        INFO("band " << b << " r " << r << " c " << c);
        REQUIRE(st[b].s0[i] == Approx(planes[3 * b][i]).margin(1e-3));
        REQUIRE(st[b].s1[i] == Approx(planes[3 * b + 1][i]).margin(1e-3));
        REQUIRE(st[b].s2[i] == Approx(planes[3 * b + 2][i]).margin(1e-3));
      }
    }
  CHECK_THROWS_WITH(demosaic_bilinear(s, raw), Catch::Contains("demosaic_color_bilinear"));
  CHECK_THROWS_WITH(simulate_raw_color(clean(), rgb, 0), Catch::Contains("colour sensor"));
}

TEST_CASE("fixed-pattern noise: same in every frame, PRNU rms as asked", "[sensor]") {
  DofpSensor s = clean(200, 200);
  s.prnu_rms = 0.02;
  s.seed = 5;
  const Field f = uniform(s, 1, 0, 0);  // 2000 e behind every polarizer
  const auto a = simulate_raw(s, f.s0, f.s1, f.s2, 0);
  CHECK(a == simulate_raw(s, f.s0, f.s1, f.s2, 1));  // no temporal noise: frames identical
  const auto [mean, var] = stats(a, s, 3);
  CHECK(mean == Approx(2000).epsilon(0.002));
  CHECK(std::sqrt(var) == Approx(0.02 * 2000).epsilon(0.05));  // 40 DN rms over 10^4 pixels
  s.seed = 6;
  CHECK(a != simulate_raw(s, f.s0, f.s1, f.s2, 0));  // another camera, another pattern
  s.prnu_rms = 0;
  s.dsnu_e = 3;
  const auto d = simulate_raw(s, f.s0, f.s1, f.s2, 0);
  const auto [dmean, dvar] = stats(d, s, 0);
  CHECK(dmean == Approx(2000).epsilon(0.002));
  CHECK(std::sqrt(dvar) == Approx(3).epsilon(0.08));
  s.dsnu_e = -1;
  CHECK_THROWS_WITH(validate(s), "dsnu_e must be >= 0");
}

TEST_CASE("clipped pixels: the demosaic's whole footprint of every raw value at the well or the ADC's top",
          "[sensor]") {
  // The clip level: 4 read-noise σ below the well in DN, or the ADC's top.
  DofpSensor s = clean(32, 32);
  s.full_well_e = 10500;
  s.gain_dn_per_e = 0.39;
  s.read_noise_e = 2.3;
  s.adc_bits = 12;
  CHECK(clip_level_dn(s) == std::floor(0.39 * (10500 - 4 * 2.3)));  // 4091, below 4095
  s.gain_dn_per_e = 1;
  CHECK(clip_level_dn(s) == 4095);
  // Every pixel of a field far past the well is flagged whatever its read noise; at 90 % of the
  // well (the brightest polarizer of a field at DoLP 0.5), none.
  s.gain_dn_per_e = 0.39;
  const Field bright = uniform(s, 1e3f, 0, 0);
  for (auto v : clipped_pixels(s, simulate_raw(s, bright.s0, bright.s1, bright.s2, 0))) REQUIRE(v == 1);
  const float s0 = static_cast<float>(0.9 * 10500 / 4e6 / 0.75);  // brightest polarizer: ½·S0·1.5
  const Field below = uniform(s, s0, 0.5f * s0, 0);
  for (auto v : clipped_pixels(s, simulate_raw(s, below.s0, below.s1, below.s2, 0))) REQUIRE(v == 0);

  // The footprint, against the demosaic itself: one raw pixel at the clip level in a dim mosaic
  // flags exactly the (2·reach + 1)² box around it, and every output pixel that the raw pixel
  // changes lies in that box (reach 1 on the mono lattices of period 2, 3 on the colour ones of 4).
  for (const bool colour : {false, true}) {
    DofpSensor t = clean(24, 20);
    t.adc_bits = 12;
    if (colour) t.color_filter = ColorFilter::rggb_blocks;
    const int reach = colour ? 3 : 1;
    CHECK(demosaic_reach(t) == reach);
    for (const auto& [r0, c0] : std::vector<std::pair<int, int>>{{9, 11}, {0, 0}, {19, 23}, {1, 22}}) {
      INFO((colour ? "colour" : "mono") << " raw pixel (" << r0 << ", " << c0 << ")");
      std::vector<std::uint16_t> raw(24 * 20, 100), hit = raw;
      hit[static_cast<std::size_t>(r0 * 24 + c0)] = 4095;
      const auto flagged = clipped_pixels(t, hit);
      // The sensor stage's mask erosion masks the same box around a pixel that sees no sky: every
      // output pixel whose demosaic reads it.
      std::vector<float> mask(24 * 20, 1.0f);
      mask[static_cast<std::size_t>(r0 * 24 + c0)] = 0.0f;
      erode_mask(mask, 24, 20, demosaic_reach(t));
      for (std::size_t i = 0; i < mask.size(); ++i) REQUIRE(mask[i] == (flagged[i] ? 0.0f : 1.0f));
      const auto stokes = [&](const std::vector<std::uint16_t>& m) {
        return colour ? demosaic_color_bilinear(t, m) : std::array<StokesPlanes, 3>{demosaic_bilinear(t, m)};
      };
      const auto before = stokes(raw), after = stokes(hit);
      int farthest = 0;  // the farthest output pixel the raw pixel changes (Chebyshev distance)
      for (int r = 0; r < 20; ++r)
        for (int c = 0; c < 24; ++c) {
          const auto i = static_cast<std::size_t>(r * 24 + c);
          const bool in_box = std::abs(r - r0) <= reach && std::abs(c - c0) <= reach;
          REQUIRE(flagged[i] == (in_box ? 1 : 0));
          for (std::size_t b = 0; b < (colour ? 3u : 1u); ++b) {
            const bool changed = before[b].s0[i] != after[b].s0[i] || before[b].s1[i] != after[b].s1[i] ||
                                 before[b].s2[i] != after[b].s2[i];
            if (changed) REQUIRE(in_box);
            if (changed) farthest = std::max({farthest, std::abs(r - r0), std::abs(c - c0)});
          }
        }
      CHECK(farthest == reach);  // the box is no larger than the demosaic's reach
    }
  }
}

TEST_CASE("the meter's percentile interpolates between ranks as NumPy's default does", "[sensor][exposure]") {
  // 1 … 101 shuffled: rank 0.995·100 = 99.5 lies halfway between 100 and 101.
  std::vector<float> v;
  for (int i = 101; i >= 1; --i) v.push_back(static_cast<float>(i));
  std::rotate(v.begin(), v.begin() + 37, v.end());
  CHECK(percentile_of(v, 99.5) == Approx(100.5));
  CHECK(percentile_of(v, 100) == 101);
  CHECK(percentile_of(v, 50) == 51);
  std::vector<float> ties(10, 3.0f);
  CHECK(percentile_of(ties, 99.5) == 3);
  std::vector<float> one{7.0f};
  CHECK(percentile_of(one, 99.5) == 7);
  CHECK(percentile_of(std::span<float>(), 99.5) == 0);
}

TEST_CASE("metered exposure: target × full scale at the percentile, in steps, within the range", "[sensor][exposure]") {
  DofpSensor s = clean();  // 4e6 e-/s per unit radiance
  s.full_well_e = 10000;
  s.adc_bits = 16;  // the ADC's top (65535 e- at 1 DN/e) lies beyond the well
  AutoExposure m;   // 99.5th percentile at 80 %
  CHECK(full_scale_e(s) == 10000);
  // S0 = 0.5 at the percentile: 8000 e- in t = 8000 / (4e6 · 0.5) s = 4000 µs.
  CHECK(metered_exposure_us(s, m, 0.5) == Approx(4000).epsilon(1e-12));
  m.step_us = 300;  // whole steps, rounded down so the percentile never passes the target: 3900 µs
  CHECK(metered_exposure_us(s, m, 0.5) == Approx(3900).epsilon(1e-12));
  m.step_us = 0;
  m.min_us = 5000;
  CHECK(metered_exposure_us(s, m, 0.5) == 5000);  // brighter than the camera can expose for
  m.min_us = 1;
  m.max_us = 2000;
  CHECK(metered_exposure_us(s, m, 0.5) == 2000);  // too dark for its longest exposure
  CHECK(metered_exposure_us(s, m, 0.0) == 2000);  // no light at all: the longest
  CHECK(metered_exposure_us(s, m, std::nan("")) == 2000);
  // An ADC that tops out before the well: its top is the full scale. 12 bits at 0.5 DN/e with a
  // black level of 95 DN read out (4095 − 95) / 0.5 = 8000 e-.
  s.adc_bits = 12;
  s.gain_dn_per_e = 0.5;
  s.black_level_dn = 95;
  CHECK(full_scale_e(s) == Approx(8000));
  m = AutoExposure{};
  CHECK(metered_exposure_us(s, m, 0.5) == Approx(0.8 * 8000 / (4e6 * 0.5) * 1e6));
}

TEST_CASE("bad meter settings are named", "[sensor][exposure]") {
  auto message = [](AutoExposure m) -> std::string {
    try {
      validate(m);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "valid";
  };
  CHECK(message(AutoExposure{}) == "valid");
  AutoExposure m;
  m.percentile = 0;
  CHECK_THAT(message(m), Catch::StartsWith("percentile"));
  m = {};
  m.target = 1.2;
  CHECK_THAT(message(m), Catch::StartsWith("target"));
  m = {};
  m.max_us = 0.5;  // below min_us = 1
  CHECK_THAT(message(m), Catch::StartsWith("max_us"));
  m = {};
  m.step_us = -1;
  CHECK_THAT(message(m), Catch::StartsWith("step_us"));
}
