// Throughput of the renderer and the stack writer, measured on a scene (prints nothing itself;
// `skypol bench` prints). Speed is measured here and reported as figures, never asserted in tests.
#pragma once

#include <string>

#include "render/scene.h"

namespace skypol::render {

struct BenchFigures {
  int width = 0, height = 0, spp = 1, frames = 0, threads = 0;
  double ray_setup_s = 0;        // camera rays for the stack (once per stack)
  double sky_mpix_per_s = 0;     // sky evaluation into the scene's channels, per frame
  double frame_render_ms = 0;
  double skypol_write_ms = 0;    // skypol's writer, per frame (headers, truth, temp file, rename)
  double openexr_write_ms = 0;   // OpenEXR alone writing the same pixels, same channels and settings
  double end_to_end_ms = 0;      // render + write per frame through render_scene
  double mb_per_frame = 0;       // uncompressed pixel data per frame
};

// Renders `frames` frames of `scene` (its first times) into files in `scratch_dir`, which is
// emptied afterwards.
BenchFigures bench_render(const Scene& scene, int frames, const std::string& scratch_dir);

}  // namespace skypol::render
