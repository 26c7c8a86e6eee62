#include "studies/tradeoff_setup.h"

#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "camera/lens_factory.h"
#include "camera/orientation.h"
#include "camera/presets.h"
#include "scene/scene.h"
#include "render/sensor_stage.h"
#include "scene/truth.h"

namespace skypol::studies::tradeoff {

sky::Site paper_site() { return sky::Site{43.28699, 5.40336, 0}; }

std::vector<sky::Instant> times_over(const std::string& center_iso, double window_min, int count) {
  if (count < 1) throw std::invalid_argument("times_over: count must be >= 1");
  const double c = sky::parse_iso8601(center_iso).unix_seconds;
  std::vector<sky::Instant> t;
  for (int i = 0; i < count; ++i) {
    const double f = count == 1 ? 0.5 : static_cast<double>(i) / (count - 1);
    t.push_back(sky::Instant{c + (f - 0.5) * window_min * 60.0});
  }
  return t;
}

std::shared_ptr<const camera::Camera> paper_camera(int binning, double heading_deg) {
  camera::LensSpec spec = camera::lens_spec(camera::lens_preset("fujinon_fe185c057ha1"),
                                            camera::sensor_preset("sony_imx250mzr"));
  spec.binning = binning;
  return std::make_shared<camera::Camera>(camera::make_lens(spec),
                                          camera::world_from_heading_tilt_roll(heading_deg, 0, 0));
}

camera::DofpSensor paper_sensor(int binning, double exposure_us, std::uint64_t seed) {
  camera::DofpSensor s = camera::sensor_preset("sony_imx250mzr").dofp;
  const double area = static_cast<double>(binning) * binning;
  s.width /= binning;
  s.height /= binning;
  s.exposure_us = exposure_us;
  // 70 % of the full well for polarizer radiance 1 in 1 ms (tradeoff_setup.h).
  s.electrons_per_radiance_s = 0.7 * s.full_well_e / 1e-3 * area;
  s.full_well_e *= area;
  s.dark_current_e_s *= area;
  s.read_noise_e *= binning;
  s.gain_dn_per_e /= area;
  s.seed = seed;
  camera::validate(s);
  return s;
}

stack::Stack render_stack(const StackRecipe& recipe) {
  auto cam = paper_camera(recipe.binning, recipe.heading_deg);
  const std::unique_ptr<sky::SkyModel> sky_model = sky::make_sky(recipe.sky);
  render::RenderOptions ro;
  ro.spp = recipe.spp;
  ro.channels = {"S0", "S1", "S2", "DoLP", "AoLP", "mask"};
  const render::Renderer renderer(cam, ro);
  if (recipe.sensor && (recipe.sensor->width != cam->width() || recipe.sensor->height != cam->height()))
    throw std::invalid_argument("render_stack: sensor size differs from the camera's");

  // make_truth reads only the site, the sun options and the orientation angles of a scene.
  scene::Scene scene;
  scene.site = paper_site();
  scene.camera.heading_deg = recipe.heading_deg;

  stack::Stack stack;
  stack.camera = cam;
  stack.bands = {"Y"};
  stack.frames.resize(recipe.times.size());
  for (std::size_t i = 0; i < recipe.times.size(); ++i) {
    const scene::Truth truth = scene::make_truth(scene, *cam, recipe.times[i]);
    stack.frames[i] = renderer.render(*sky_model, truth.sun);  // parallel over tiles
    stack.frames[i].truth = truth;
  }
  // The sensor is one thread per frame (its random numbers depend on the frame index only, so the
  // order does not matter): frames in parallel.
  scene::SensorSpec sensor;
  if (recipe.sensor) sensor.dofp = *recipe.sensor;
  tbb::parallel_for(std::size_t{0}, stack.frames.size(), [&](std::size_t i) {
    stack::Frame& f = stack.frames[i];
    if (recipe.sensor) render::apply_sensor(sensor, {"Y"}, i, f, recipe.keep_raw);
    if (!recipe.keep_stokes) {
      for (const char* c : {"S0.Y", "S1.Y", "S2.Y"}) f.channels.erase(c);
    }
  });
  return stack;
}

}  // namespace skypol::studies::tradeoff
