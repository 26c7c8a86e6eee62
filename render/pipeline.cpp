#include "render/pipeline.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <utility>

#include "render/occluders_embree.h"
#include "stack/preview.h"
#include "render/renderer.h"
#include "render/sensor_stage.h"
#include "stack/stack_io.h"
#include "scene/truth.h"

namespace skypol::render {
namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The last stack's frame, kept for the next stack on this thread (a sweep renders one stack per
// variant): its pixel memory is already allocated and touched, so a next stack of the same size
// pays neither the allocation nor the page faults ("into a new frame" in `skypol bench`).
thread_local stack::Frame t_spare_frame;
}  // namespace

RenderReport render_scene(const scene::Scene& scene, const std::string& out_path,
                          const std::function<void(std::size_t, std::size_t)>& progress,
                          const std::optional<std::filesystem::path>& table_cache_dir) {
  RenderReport report;
  report.path = out_path;
  report.frames = scene.times.size();

  const auto t_setup = Clock::now();
  std::shared_ptr<const camera::Camera> cam = scene::build_camera(scene.camera);
  // One model for every band (grey skies), or one per band (vrte: tables from the cache).
  const sky::BandSkies skies = scene::build_band_skies(scene, table_cache_dir ? *table_cache_dir : sky::default_table_cache_dir());
  std::vector<const sky::SkyModel*> band_skies;
  for (const auto& m : skies.skies) band_skies.push_back(m.get());
  report.tables_built = skies.tables_built;
  report.tables_read = skies.tables_read;
  report.width = cam->width();
  report.height = cam->height();
  std::vector<scene::Truth> truths;
  for (sky::Instant t : scene.times) truths.push_back(scene::make_truth(scene, *cam, t));
  RenderOptions ro;
  ro.spp = scene.render.spp;
  ro.seed = scene.render.seed;
  ro.bands = scene.render.bands;
  ro.channels = scene.output.channels;
  std::vector<std::string> written = channel_names(ro);
  const bool keep_raw = std::find(ro.channels.begin(), ro.channels.end(), "raw") != ro.channels.end();
  if (keep_raw) written.emplace_back("raw");
  // A sensor measures S0, S1, S2 whatever the file keeps, and previews show them;
  // the writer writes only what the file keeps.
  std::vector<const char*> needed;
  if (scene.sensor || scene.output.previews) needed = {"S0", "S1", "S2"};
  // The sensor stage needs the mask to zero (and erode) what sees no sky, even when the file
  // does not keep it.
  if (scene.sensor || scene.output.previews) needed.push_back("mask");
  for (const char* s : needed) {
    if (std::find(ro.channels.begin(), ro.channels.end(), s) == ro.channels.end()) ro.channels.emplace_back(s);
  }
  std::optional<stack::PreviewFolder> previews;
  if (scene.output.previews) previews.emplace(stack::preview_folder_for(out_path));
  const Renderer renderer(cam, ro, make_occluders(scene.occluders));  // null without occluders
  // Refilled for every part: pixel memory is allocated once per stack, or not at all when the
  // previous stack left its frame (render() resizes the channels, reusing what fits).
  stack::Frame f = t_spare_frame.channels.empty() ? renderer.new_frame() : std::exchange(t_spare_frame, {});
  report.setup_seconds = since(t_setup);

  stack::StackHeader header;
  header.bands = scene.render.bands;
  header.camera_description = scene.camera.description;
  header.scene_text = scene.text;
  header.sky_model = band_skies.front()->name();
  stack::WriteOptions wo;
  wo.half = scene.output.half;
  wo.compression = scene.output.compression;
  wo.zip_level = scene.output.zip_level;

  const auto t_total = Clock::now();
  double render_s = 0;
  stack::write_stack_reusing(out_path, truths, written, cam->width(), cam->height(), header, wo,
                      [&](std::size_t i) -> const stack::Frame& {
    if (progress && i > 0) progress(i, truths.size());
    const auto t0 = Clock::now();
    renderer.render(band_skies, truths[i].sun, f);
    if (scene.sensor) apply_sensor(*scene.sensor, scene.render.bands, i, f, keep_raw);
    render_s += since(t0);
    f.truth = truths[i];
    if (previews) previews->add(i, f, *cam, scene.render.bands.front());
    // The writer reads only the channels the file keeps; the others (what a sensor or the previews
    // needed) stay in the frame, whose memory the next part reuses.
    return f;
  });
  t_spare_frame = std::move(f);
  if (previews) previews->commit();
  if (progress) progress(truths.size(), truths.size());
  report.render_seconds = render_s;
  report.write_seconds = since(t_total) - render_s;
  return report;
}

}  // namespace skypol::render
