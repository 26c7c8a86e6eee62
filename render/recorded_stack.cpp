// Stacks recorded in memory, ideal or through a DoFP sensor (recorded_stack.h).
#include "render/recorded_stack.h"

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "camera/camera.h"
#include "camera/orientation.h"
#include "render/renderer.h"
#include "render/sensor_stage.h"
#include "scene/truth.h"

namespace skypol::render {

stack::Stack record_stack(const RecordingSetup& setup, const std::vector<sky::Instant>& times) {
  if (!setup.lens) throw std::invalid_argument("record_stack: no lens");
  // Grey skies: make_sky's one model. vrte: the band's table, from the default cache.
  sky::SiteAtmosphere air;
  if (setup.sun_options.pressure_hpa > 0) air.pressure_hpa = setup.sun_options.pressure_hpa;
  air.altitude_m = setup.site.height_m;
  air.latitude_deg = setup.site.latitude_deg;
  if (setup.bands.empty()) throw std::invalid_argument("record_stack: no band");
  const sky::BandSkies skies = sky::make_band_skies(setup.sky, setup.bands, air, sky::default_table_cache_dir());
  std::vector<const sky::SkyModel*> band_skies;
  for (const auto& m : skies.skies) band_skies.push_back(m.get());
  auto cam = std::make_shared<camera::Camera>(
      setup.lens,
      camera::world_from_heading_tilt_roll(setup.heading_deg, setup.tilt_deg, setup.roll_deg));
  // make_truth reads the site, the sun options and the orientation angles from a scene.
  scene::Scene scene;
  scene.site = setup.site;
  scene.sun_options = setup.sun_options;
  scene.camera.heading_deg = setup.heading_deg;
  scene.camera.tilt_deg = setup.tilt_deg;
  scene.camera.roll_deg = setup.roll_deg;

  RenderOptions options;
  options.bands = setup.bands;
  options.channels = {"S0", "S1", "S2", "DoLP", "AoLP", "mask"};
  const Renderer renderer(cam, options);
  stack::Stack stack;
  stack.camera = cam;
  stack.bands = setup.bands;
  for (const sky::Instant t : times) {
    const scene::Truth truth = scene::make_truth(scene, *cam, t);
    stack::Frame f = renderer.render(band_skies, truth.sun);
    f.truth = truth;
    stack.frames.push_back(std::move(f));
  }
  return stack;
}

stack::Stack through_sensor(const stack::Stack& ideal, camera::DofpSensor sensor,
                            const std::optional<camera::AutoExposure>& auto_exposure) {
  stack::Stack out;
  out.camera = ideal.camera;
  out.bands = ideal.bands;
  out.camera_description = ideal.camera_description;
  out.scene_text = ideal.scene_text;
  if (ideal.frames.empty()) return out;
  const int w = ideal.frames.front().width, h = ideal.frames.front().height;
  scene::SensorSpec spec;
  spec.dofp = sensor;
  spec.dofp.width = w;
  spec.dofp.height = h;
  camera::validate(spec.dofp);
  if (auto_exposure) camera::validate(*auto_exposure);
  spec.auto_exposure = auto_exposure;
  const std::vector<std::uint8_t> sky =
      auto_exposure && ideal.camera ? sky_pixels(*ideal.camera) : std::vector<std::uint8_t>{};
  const std::vector<std::string>& bands = ideal.bands;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);

  // apply_sensor erodes the mask by the demosaic's reach, so the ideal mask goes in.
  const std::vector<float>& mask = ideal.frames.front().channel("mask");

  for (std::size_t i = 0; i < ideal.frames.size(); ++i) {
    const stack::Frame& f = ideal.frames[i];
    stack::Frame g;
    g.width = w;
    g.height = h;
    g.truth = f.truth;
    for (const std::string& c : sensor_inputs(bands)) g.channels[c] = f.channel(c);
    for (const std::string& b : bands) {
      g.channels["DoLP." + b].assign(n, 0.0f);
      g.channels["AoLP." + b].assign(n, 0.0f);
    }
    g.channels["mask"] = mask;
    apply_sensor(spec, bands, i, g, false, sky);
    for (const std::string& c : sensor_inputs(bands)) g.channels.erase(c);
    out.frames.push_back(std::move(g));
  }
  return out;
}

}  // namespace skypol::render
