// The one set-up every `skypol tradeoff` study varies: the SkyPole paper's (Marseille,
// 23 September 2022, a zenith camera with the 185° Fujinon 1.8 mm fisheye on the Sony IMX250MZR,
// camera/presets.h), rendered into an in-memory stack with the truth the renderer would write, and
// optionally seen through the DoFP sensor (shot and read noise, mosaic, bilinear demosaic) before
// DoLP and AoLP are formed. A study changes one knob of this and measures.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/dofp_sensor.h"
#include "stack/frame.h"
#include "render/renderer.h"
#include "sky/sky_spec.h"
#include "sky/sun.h"
#include "sky/time.h"

namespace skypol::studies::tradeoff {

// The paper's roof: 43.28699 N 5.40336 E.
sky::Site paper_site();

// Frames `count` (≥ 1) spread evenly over [center − window/2, center + window/2] (the centre
// alone for count 1). Solar noon in Marseille on the paper's day is about 11:31 UTC.
std::vector<sky::Instant> times_over(const std::string& center_iso, double window_min, int count);

// The paper's lens on the paper's sensor, binned b×b (b = 1: 2448×2048; b = 4: 612×512), at the
// zenith with image-up towards azimuth heading_deg.
std::shared_ptr<const camera::Camera> paper_camera(int binning, double heading_deg);

// The IMX250MZR preset exposed for `exposure_us`, scaled for b×b binning as a sensor with b×
// larger pixels (signal, dark current and full well ×b², read noise ×b, gain ÷b²).
// electrons_per_radiance_s is set so that radiance 1 fills 70 % of the full well at 1000 µs: 1 is
// the most a pixel behind a polarizer sees of a Rayleigh sky (½·S0·(1 + DoLP) = ½(1 + cos²γ +
// Pmax·sin²γ) ≤ 1), so 1 ms is the well-exposed default and clipping starts near 1.4 ms.
camera::DofpSensor paper_sensor(int binning, double exposure_us, std::uint64_t seed);

struct StackRecipe {
  int binning = 4;
  double heading_deg = 0;
  std::vector<sky::Instant> times;
  sky::SkySpec sky;                          // default: Rayleigh, Pmax 1
  int spp = 1;
  std::optional<camera::DofpSensor> sensor;  // none: noise-free Stokes
  bool keep_stokes = false;                  // keep S0, S1, S2 (else DoLP, AoLP, mask only)
  bool keep_raw = false;                     // with a sensor: keep its raw mosaic as channel "raw"
};

// Renders the recipe with render::Renderer (band "Y"). With a sensor, each frame goes through the
// pipeline's own sensor stage (render/sensor_stage.h; frame index = its position in the stack).
stack::Stack render_stack(const StackRecipe& recipe);

}  // namespace skypol::studies::tradeoff
