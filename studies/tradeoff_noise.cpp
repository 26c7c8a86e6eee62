// Study 4: sensor noise. The paper's day (06:00–17:00 UTC, hourly) at 4×4 binning through the
// IMX250MZR-like DoFP sensor (studies/tradeoff_setup.h) at exposures from 30 µs (few electrons: shot
// and read noise) to 4 ms (the brightest pixels clip at the full well from about 1.4 ms), plus the
// noise-free stack; three headings.
// Beside every estimator's error: the noon frame's DoLP error (RMS against the noise-free DoLP over
// the sky pixels: noise, demosaic error and the polarizers' finite extinction together) and the
// fraction of its sky pixels that clip.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "camera/dofp_sensor.h"
#include "studies/tradeoff_scoring.h"
#include "studies/tradeoff_setup.h"
#include "studies/tradeoff_studies.h"

namespace skypol::studies::tradeoff {
namespace {

struct FrameNoise {
  double dolp_rms = 0;  // RMS of DoLP after the sensor − noise-free DoLP
  double clipped = 0;  // fraction of sky pixels at the ADC's or the well's top
};

// What the sensor did to one frame: its DoLP against the noise-free twin's, and its raw mosaic's
// clipped pixels (camera::clip_level_dn), over the sky pixels a camera pipeline would read. Those
// are the sensor's own mask (the clean one eroded by the pixel ring where the demosaic mixes in the
// darkness beyond the image circle, render/sensor_stage.h) with the clipped pixels it also masks
// put back: their DoLP error is what this study shows.
FrameNoise frame_noise(const camera::DofpSensor& sensor, const stack::Frame& noisy, const stack::Frame& clean) {
  const double top = camera::clip_level_dn(sensor);
  const auto& raw = noisy.channel("raw");
  const std::vector<std::uint16_t> readings(raw.begin(), raw.end());  // the channel holds them exactly
  const std::vector<std::uint8_t> clipped_footprint = camera::clipped_pixels(sensor, readings);
  const auto& dolp = noisy.channel("DoLP.Y");
  const auto& mask = noisy.channel("mask");
  const auto& clean_mask = clean.channel("mask");
  const auto& truth = clean.channel("DoLP.Y");
  double ss = 0;
  int n = 0, clipped = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (mask[i] < 1 && !(clipped_footprint[i] && clean_mask[i] >= 1)) continue;
    const double d = static_cast<double>(dolp[i]) - static_cast<double>(truth[i]);
    ss += d * d;
    clipped += static_cast<double>(raw[i]) >= top;
    ++n;
  }
  return {n ? std::sqrt(ss / n) : 0, n ? static_cast<double>(clipped) / n : 0};
}

}  // namespace

void study_noise(const StudyOptions& o) {
  const int b = o.small ? 16 : 4;
  const std::vector<double> exposures =
      o.small ? std::vector<double>{100, 1000, 4000} : std::vector<double>{30, 100, 300, 1000, 1500, 2000, 4000};
  const std::vector<double> headings = o.small ? std::vector<double>{15} : std::vector<double>{15, 140, 260};
  const std::vector<sky::Instant> times =
      o.small ? times_over("2022-09-23T12:00:00Z", 480, 5) : times_over("2022-09-23T11:30:00Z", 660, 12);
  const double default_exposure_us = 1000;
  Table t(with_score_columns({"exposure_us", "noise", "binning", "width", "height", "frames", "heading_deg",
                              "dolp_error_rms", "clipped_fraction", "is_default"}));
  int seed = 1;
  for (const double heading : headings) {
    StackRecipe clean_recipe;
    clean_recipe.binning = b;
    clean_recipe.heading_deg = heading;
    clean_recipe.times = times;
    clean_recipe.sky.max_dolp = 0.7;
    clean_recipe.keep_stokes = true;
    const stack::Stack clean = render_stack(clean_recipe);
    const std::size_t noon = times.size() / 2;
    score_every_method(clean, t, [&](Table& row) {
      row.set("noise", "none").set("binning", b).set("width", clean.camera->width())
          .set("height", clean.camera->height()).set("frames", static_cast<int>(times.size()))
          .set("heading_deg", heading).set("dolp_error_rms", 0.0).set("clipped_fraction", 0.0)
          .set("is_default", false);
    });
    for (const double exposure : exposures) {
      StackRecipe r = clean_recipe;
      r.keep_stokes = false;
      r.keep_raw = true;
      r.sensor = paper_sensor(b, exposure, static_cast<std::uint64_t>(seed++));
      const stack::Stack stack = render_stack(r);
      const FrameNoise fn = frame_noise(*r.sensor, stack.frames[noon], clean.frames[noon]);
      score_every_method(stack, t, [&](Table& row) {
        row.set("exposure_us", exposure).set("noise", "sensor").set("binning", b)
            .set("width", stack.camera->width()).set("height", stack.camera->height())
            .set("frames", static_cast<int>(times.size())).set("heading_deg", heading)
            .set("dolp_error_rms", fn.dolp_rms).set("clipped_fraction", fn.clipped)
            .set("is_default", exposure == default_exposure_us);
      });
    }
  }
  t.write((std::filesystem::path(o.out_dir) / "noise.csv").string());
}

}  // namespace skypol::studies::tradeoff
