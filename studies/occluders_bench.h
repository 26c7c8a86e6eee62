// Throughput of the occlusion test on a scene's own camera and occluders (prints nothing itself;
// `skypol bench-occluders` prints). Speed is measured here and reported as figures, never asserted
// in tests.
#pragma once

#include <cstddef>

#include "scene/scene.h"

namespace skypol::studies {

struct OccluderBenchFigures {
  int width = 0, height = 0, threads = 0, repeats = 0;
  std::size_t triangles = 0;
  std::size_t rays = 0;            // traced per pass: the pixel centres inside the image circle
  double occluded_fraction = 0;    // of the traced rays
  double build_ms = 0;             // Embree device, geometry and BVH
  double trace_ms = 0;             // one pass over the frame, best of `repeats`
  double mrays_per_s = 0;          // rays / trace time
  // The same pass in CPU time, all threads together (best of `repeats`): on a machine that other
  // work shares, wall time overstates the cost and this figure shows what a core achieves.
  double trace_cpu_ms = 0;
  double mrays_per_cpu_s = 0;
  double frame_mpix_per_s = 0;     // width·height / trace time (the whole frame's worth of pixels)
  double setup_ms_without = 0;     // the renderer's per-stack ray set-up without occluders
  double setup_ms_with = 0;        // … and with them (camera rays + occlusion), best of `repeats`
};

// Needs a scene with occluders (throws std::invalid_argument otherwise); renders at spp 1.
OccluderBenchFigures bench_occluders(const scene::Scene& scene, int repeats);

}  // namespace skypol::studies
