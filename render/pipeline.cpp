#include "render/pipeline.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "render/occluders_embree.h"
#include "stack/preview.h"
#include "render/renderer.h"
#include "render/sensor_stage.h"
#include "scene/scene_error.h"
#include "scene/scene_source.h"
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
thread_local stack::Frame t_spare_second;  // an overlapped write's second frame (render_scene)
// A banded write's two bands (render_scene), kept likewise.
thread_local std::array<stack::Frame, 2> t_spare_bands;
// Rows per band: a multiple of the renderer's 16-row tiles. 256 rows of DoLP and AoLP at 2448
// pixels are 5 MB a band; 128 rows cost more hand-overs between the threads for no less CPU, and
// 512 or 1024 rows more memory to fault in (alternating runs of the 23-frame job, 2026-12-02).
constexpr int kBandRows = 256;

// A render in which no pixel sees the sky, or next to none (fewer than 1 in 10 000), is a
// mistake in the scene (focal_mm in metres gives an image circle of a pixel or two; a camera facing
// the ground sees none), refused before anything is written, naming the likely key. A pixel sees
// the sky when its centre has a ray (inside the image circle) above the horizon. A grid of every
// 8th pixel answers for every sane camera; only a suspicious one pays for counting every pixel.
void refuse_blind_camera(const scene::Scene& scene, const camera::Camera& cam) {
  const int w = cam.width(), h = cam.height();
  const double needed = std::max(1.0, 1e-4 * w * h);
  const auto count = [&](int step, bool* any_ray) {
    double n = 0;
    for (int y = step / 2; y < h; y += step) {
      for (int x = step / 2; x < w; x += step) {
        const auto r = cam.ray(Eigen::Vector2d(x, y));
        if (r && any_ray) *any_ray = true;
        if (r && r->d.z() > 0) n += 1;
      }
    }
    return n;
  };
  if (w >= 64 && h >= 64 && count(8, nullptr) * 64 >= 4 * needed) return;
  bool any_ray = false;
  const double seen = count(1, &any_ray);
  if (seen >= needed) return;
  const camera::LensSpec& l = scene.camera.lens;
  const camera::Intrinsics& k = cam.lens().intrinsics();
  char buf[320];
  const char* key = "camera";
  if (any_ray && seen == 0) {
    key = "camera.tilt_deg";
    std::snprintf(buf, sizeof buf, "every pixel looks below the horizon: check camera.tilt_deg (%g; 0 looks at the "
                  "zenith, 90 at the horizon)", scene.camera.tilt_deg);
  } else {
    // A pixel or two inside the image circle: the scale is the usual culprit.
    const double radius_px = k.fx * cam.lens().max_field_angle();
    const int n = std::snprintf(buf, sizeof buf, "the image circle has a radius of about %.3g px: ", radius_px);
    char* rest = buf + n;
    const std::size_t room = sizeof buf - static_cast<std::size_t>(n);
    if (l.focal_mm) {
      key = "camera.focal_mm";
      std::snprintf(rest, room, "check camera.focal_mm = %g (millimetres, not metres) and camera.pitch_um = %g "
                    "(micrometres)", *l.focal_mm, l.pitch_um.value_or(0));
    } else if (l.fx) {
      key = "camera.fx";
      std::snprintf(rest, room, "check camera.fx = %g (pixels) and camera.cx, camera.cy", *l.fx);
    } else {
      std::snprintf(rest, room, "check the camera's scale and principal point (camera.cx, camera.cy)");
    }
  }
  // At the key's line in the scene file when the file writes it; else the file's first line (the
  // value came from a preset, a default or --set).
  const scene::FileLoc where = scene::locate_key(scene.file, key).value_or(scene::FileLoc{scene.file, 1, 1});
  throw scene::SceneError(where,
                          (seen == 0 ? std::string("no pixel of the ")
                                     : "only " + std::to_string(static_cast<long>(seen)) + " pixel(s) of the ") +
                              std::to_string(w) + "x" + std::to_string(h) + " image " + (seen == 0 ? "sees" : "see") +
                              " the sky; " + buf);
}

// The last stack's camera rays and the camera they were traced for: a sweep's next variant that
// keeps the camera (and has no occluders) reuses them instead of tracing every pixel again. The
// key is the camera's canonical scene text plus the built lens's name and parameters at full
// precision (an OCamCalib file's contents are not in the text).
struct PlanesCache {
  std::string key;
  std::shared_ptr<const RayPlanes> planes;
};
thread_local PlanesCache t_planes;

std::string planes_key(const scene::Scene& scene, const camera::Camera& cam) {
  std::string key = scene.camera.description + "\n" + cam.lens().name();
  char buf[64];
  for (const auto& [name, value] : cam.lens().parameters()) {
    std::snprintf(buf, sizeof buf, " %.17g", value);
    key += " " + name + buf;
  }
  return key;
}
}  // namespace

RenderReport render_scene(const scene::Scene& scene, const std::string& out_path,
                          const std::function<void(std::size_t, std::size_t)>& progress,
                          const std::optional<std::filesystem::path>& table_cache_dir) {
  RenderReport report;
  report.path = out_path;
  report.frames = scene.times.size();

  const auto t_setup = Clock::now();
  std::shared_ptr<const camera::Camera> cam = scene::build_camera(scene.camera);
  refuse_blind_camera(scene, *cam);
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
  // One frame: its rays are used once, so they are traced per tile, never stored (unless a
  // previous stack left planes for this camera).
  ro.keep_rays = truths.size() > 1;
  // The frames below are this function's own (and the next stack's): nothing but the renderer
  // and the sensor stage, which resets the token, writes them.
  ro.reuse_cleared = true;
  const std::vector<std::string> written = kept_channels(channel_names(ro), ro.channels, scene.sensor.has_value());
  const bool keep_raw = std::find(written.begin(), written.end(), "raw") != written.end();
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
  std::shared_ptr<const Occluders> occluders = make_occluders(scene.occluders);  // null without occluders
  const std::string key = occluders || ro.spp != 1 ? std::string() : planes_key(scene, *cam);
  const bool reuse = !key.empty() && t_planes.planes && t_planes.key == key &&
                     t_planes.planes->tile_rows() == ro.tile_rows;
  const Renderer renderer(cam, ro, occluders, reuse ? t_planes.planes : nullptr);
  if (!key.empty() && renderer.ray_planes()) t_planes = {key, renderer.ray_planes()};

  stack::StackHeader header;
  header.bands = scene.render.bands;
  header.camera_description = scene.camera.description;
  header.scene_text = scene.text;
  header.sky_model = band_skies.front()->name();
  header.exposures = scene.sensor.has_value();
  if (scene.sensor) header.polarizer_angles = polarizer_angles(*scene.sensor);
  // The meter's region, one camera for the whole stack: computed only for auto exposure.
  const std::vector<std::uint8_t> sky =
      scene.sensor && scene.sensor->auto_exposure ? sky_pixels(*cam) : std::vector<std::uint8_t>{};
  stack::WriteOptions wo;
  wo.half = scene.output.half;
  wo.compression = scene.output.compression;
  wo.zip_level = scene.output.zip_level;
  const bool banded = stack::encodes_on_calling_thread(wo) && !scene.sensor && !previews && ro.spp == 1;
  // Refilled for every part: pixel memory is allocated once per stack, or not at all when the
  // previous stack left its frame (render() resizes the channels, reusing what fits). A banded
  // write needs no frame.
  stack::Frame frame;
  if (!banded) frame = t_spare_frame.channels.empty() ? renderer.new_frame() : std::exchange(t_spare_frame, {});
  report.setup_seconds = since(t_setup);

  double render_s = 0;
  const auto t_total = Clock::now();
  auto fill = [&](std::size_t i, stack::Frame& f) {
    if (progress && i > 0) progress(i, truths.size());
    const auto t0 = Clock::now();
    renderer.render(band_skies, truths[i].sun, f);
    if (scene.sensor) apply_sensor(*scene.sensor, scene.render.bands, i, f, keep_raw, sky);
    render_s += since(t0);
    f.truth = truths[i];
    if (previews) previews->add(i, f, *cam, scene.render.bands.front());
    // The writer reads only the channels the file keeps; the others (what a sensor or the
    // previews needed) stay in the frame, whose memory a later part reuses.
  };
  if (banded) {
    // Uncompressed, nothing that needs whole frames: each part is rendered and written in bands
    // of rows, the next band rendering on the other core while OpenEXR copies this one. The
    // pixel memory is two bands, faulted in once, instead of two frames (80 MB for DoLP and AoLP
    // of the paper's camera), whose first touch is a large share of a many-frame job's CPU; and
    // writing starts after one band, not one frame (docs/benchmarks.md section 9).
    report.write_seconds = stack::write_stack_banded(
        out_path, truths, written, cam->width(), cam->height(), header, wo, kBandRows, t_spare_bands,
        [&](std::size_t i, int y0, int y1, stack::Frame& band) {
          if (progress && i > 0 && y0 == 0) progress(i, truths.size());
          const auto t0 = Clock::now();
          renderer.render_rows(band_skies, truths[i].sun, y0, y1, band);
          render_s += since(t0);
        });
  } else if (truths.size() > 1 && stack::encodes_on_calling_thread(wo)) {
    // Uncompressed: OpenEXR copies on this thread alone, so part i + 1 renders on the other core
    // meanwhile, into a second frame (kept for the next stack too). A compressed stack's encoding
    // already uses both cores, where overlapping adds CPU and wall time, so those parts are written
    // in turn (the measurements: docs/benchmarks.md section 9).
    std::array<stack::Frame, 2> frames{std::move(frame), t_spare_second.channels.empty()
                                                             ? renderer.new_frame()
                                                             : std::exchange(t_spare_second, {})};
    report.write_seconds = stack::write_stack_overlapped(out_path, truths, written, cam->width(), cam->height(),
                                                         header, wo, frames, fill);
    frame = std::move(frames[0]);
    t_spare_second = std::move(frames[1]);
  } else {
    stack::write_stack_reusing(out_path, truths, written, cam->width(), cam->height(), header, wo,
                               [&](std::size_t i) -> const stack::Frame& {
                                 fill(i, frame);
                                 return frame;
                               });
    report.write_seconds = since(t_total) - render_s;
  }
  if (!banded) t_spare_frame = std::move(frame);
  if (previews) previews->commit();
  if (progress) progress(truths.size(), truths.size());
  report.render_seconds = render_s;
  return report;
}

}  // namespace skypol::render
