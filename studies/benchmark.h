// Throughput of the renderer and the stack writer, measured on a scene (prints nothing itself;
// `skypol bench` prints). Speed is measured here and reported as figures, never asserted in tests.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace skypol::studies {

// Where and how the figures were measured: they mean little without it.
struct BenchContext {
  std::string cpu;            // "model name" of /proc/cpuinfo ("unknown" elsewhere)
  int hardware_threads = 0;   // std::thread::hardware_concurrency()
  int tbb_threads = 0;        // threads the renderer uses
  std::string build_type;     // CMAKE_BUILD_TYPE of this build
  std::string compiler;
  std::string date_utc;       // ISO 8601, when the measurement started
  double load_average = -1;   // 1-minute load average at the start (-1: unknown); others' load skews figures
};

BenchContext bench_context();

struct BenchFigures {
  BenchContext context;
  int width = 0, height = 0, spp = 1, frames = 0;
  std::vector<std::string> channels;
  std::string compression;
  bool half = false;
  double mb_per_frame = 0;          // uncompressed pixel data per frame
  double ray_setup_ms = 0;          // camera rays for the stack (once per stack)
  double frame_alloc_ms = 0;        // a frame's channels allocated and first touched (once per stack)
  double frame_render_ms = 0;       // sky evaluation into a reused frame, mean per frame
  double frame_render_best_ms = 0;  // the fastest frame (others' load on a shared machine only adds)
  double sky_mpix_per_s = 0;        // width·height / frame_render_ms
  double sky_mpix_per_s_best = 0;   // width·height / frame_render_best_ms
  double fresh_frame_render_ms = 0; // the same into a newly allocated frame (page faults included)
  double openexr_write_ms = 0;      // OpenEXR alone writing the same pixels, same channels and settings
  double openexr_write_best_ms = 0;
  double skypol_write_ms = 0;       // skypol's writer, per frame (headers, truth, temp file, rename)
  double skypol_write_best_ms = 0;
  double render_and_write_best_ms = 0;  // the fastest round's render + skypol write
  double end_to_end_ms = 0;         // render_scene's wall time per frame, set-up excluded
  // OpenEXR alone writing the last frame with zip at each level asked for (1 fastest .. 9 smallest;
  // OpenEXR's default is 4); the scene's own compression and pixel type are not changed.
  struct ZipLevel {
    int level = 0;
    double write_ms = 0;  // best of the rounds
    double mb = 0;        // file size
  };
  std::vector<ZipLevel> zip_levels;
};

// Renders `frames` frames of `scene` (its first times, cycled if it has fewer) and writes them
// into files in `scratch_dir`, which is emptied afterwards. Timings are means over the frames.
// render_only: the write figures stay 0 (a quick look at the renderer alone).
// zip_levels: also time OpenEXR alone writing a frame with zip at each of these levels (BenchFigures::zip_levels).
BenchFigures bench_render(const scene::Scene& scene, int frames, const std::string& scratch_dir, bool render_only = false,
                          const std::vector<int>& zip_levels = {});

}  // namespace skypol::studies
