// Study 6: throughput and its scaling. The paper's scene (studies/tradeoff_setup.h, noise-free) at
// several binnings with 8 frames, and at 4×4 binning with 4 to 32 frames, through the real
// pipeline: render::render_scene (camera rays once, sky per frame, EXR encode and write with the
// scene defaults: float, zip, S0 S1 S2 DoLP AoLP mask), stack::read_stack, then every estimator
// on the stack read back. MB are uncompressed pixel data (what the renderer hands the writer).
// The Rayleigh-law misfit (skypole/sun_vector.h) has a row of its own: four methods' answers
// include it (their model gates, skypole/calibration_gates.cpp), so their times hold it too.
// Mrays/s with occluders is a placeholder row: `skypol bench-occluders` measures Embree on the
// urban canyon, and scripts/benchmarks fills the row from it.
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "studies/tradeoff_setup.h"
#include "studies/tradeoff_studies.h"
#include "studies/tradeoff_table.h"
#include "render/pipeline.h"
#include "scene/scene.h"
#include "stack/stack_io.h"
#include "skypole/evaluate.h"
#include "skypole/sun_vector.h"

namespace skypol::studies::tradeoff {
namespace {

namespace fs = std::filesystem;

// The paper's scene at b×b binning with `frames` frames spread over 06:00–17:00 UTC.
std::string scene_text(int b, int frames, const std::string& out) {
  std::string instants;
  for (const sky::Instant t : times_over("2022-09-23T11:30:00Z", frames > 1 ? 660 : 0, frames))
    instants += (instants.empty() ? "\"" : ", \"") + sky::format_iso8601(t) + "\"";
  char camera[256];
  std::snprintf(camera, sizeof camera,
                "[camera]\nmodel = \"equidistant\"\nfocal_mm = 1.8\npitch_um = %g\nwidth = %d\nheight = %d\n"
                "fov_deg = 185\n",
                3.45 * b, 2448 / b, 2048 / b);
  return "[site]\nlatitude_deg = " + std::to_string(paper_site().latitude_deg) +
         "\nlongitude_deg = " + std::to_string(paper_site().longitude_deg) + "\n[time]\ninstants = [" + instants +
         "]\n" + camera + "[sky]\nmax_dolp = 0.7\n[output]\npath = \"" + out + "\"\n";
}

}  // namespace

void study_throughput(const StudyOptions& o) {
  struct Config {
    int binning, frames;
  };
  std::vector<Config> configs;
  if (o.small) {
    configs = {{16, 3}, {8, 3}, {16, 6}};
  } else {
    for (const int b : {8, 4, 2, 1}) configs.push_back({b, 8});
    for (const int n : {4, 16, 32}) configs.push_back({4, n});
  }
  const fs::path scratch = fs::path(o.out_dir) / "throughput-scratch";
  fs::create_directories(scratch);
  const std::string path = (scratch / "stack.exr").string();

  Table t({"quantity", "method", "binning", "width", "height", "frames", "seconds", "rate", "unit", "mb",
           "file_mb", "note"});
  auto row = [&](const char* quantity, const Config& c, int w, int h) -> Table& {
    return t.row().set("quantity", quantity).set("binning", c.binning).set("width", w).set("height", h)
        .set("frames", c.frames);
  };
  for (const Config& c : configs) {
    const scene::Scene scene = scene::parse_scene(scene_text(c.binning, c.frames, path), "tradeoff-throughput");
    const int w = scene.camera.lens.width, h = scene.camera.lens.height;
    const render::RenderReport rep = render::render_scene(scene, path);
    const double px = static_cast<double>(w) * h * c.frames;
    const double mb = px * static_cast<double>(scene.output.channels.size()) * sizeof(float) / 1e6;
    const double file_mb = static_cast<double>(fs::file_size(path)) / 1e6;
    row("ray_setup", c, w, h).set("seconds", rep.setup_seconds).set("unit", "s/stack");
    row("sky_render", c, w, h).set("seconds", rep.render_seconds).set("rate", px / rep.render_seconds / 1e6)
        .set("unit", "Mpix/s");
    row("exr_write", c, w, h).set("seconds", rep.write_seconds).set("rate", mb / rep.write_seconds)
        .set("unit", "MB/s").set("mb", mb).set("file_mb", file_mb);
    stack::Stack stack;
    const double read_s = best_seconds(1, [&] { stack = stack::read_stack(path); });
    row("stack_read", c, w, h).set("seconds", read_s).set("rate", mb / read_s).set("unit", "MB/s").set("mb", mb)
        .set("file_mb", file_mb);
    for (const std::string& m : skypole::method_names()) {
      try {
        const double s = best_seconds(1, [&] { (void)skypole::run_method(stack, m); });
        row("estimate", c, w, h).set("method", m).set("seconds", s).set("rate", px / s / 1e6).set("unit", "Mpix/s");
      } catch (const std::invalid_argument& e) {  // too few frames for this method
        row("estimate", c, w, h).set("method", m).set("unit", "Mpix/s").set("note", e.what());
      }
    }
    const double misfit_s = best_seconds(1, [&] { (void)skypole::rayleigh_law_misfit(stack, {}); });
    row("law_misfit", c, w, h).set("seconds", misfit_s).set("rate", px / misfit_s / 1e6).set("unit", "Mpix/s")
        .set("note", "inside classic, great_circle, sun_vector and invariance's estimate times");
    fs::remove(path);
  }
  // Rays against Embree occluders: measured by `skypol bench-occluders` (studies/occluders_bench.h).
  t.row().set("quantity", "occluded_rays").set("unit", "Mrays/s")
      .set("note", "placeholder: scripts/benchmarks fills it from `skypol bench-occluders`");
  fs::remove_all(scratch);
  t.write((fs::path(o.out_dir) / "throughput.csv").string());
}

}  // namespace skypol::studies::tradeoff
