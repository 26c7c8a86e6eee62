// Camera-ray throughput per lens model (`skypol bench --rays`): every pixel of a full sensor
// through Lens::ray_row (and Camera::ray_row, what the renderer calls), against the per-pixel ray() that the base ray_row calls, with the round
// trip project(ray_row(p)) − p and ray_row's distance from ray(). Figures only, never asserted.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "camera/lens.h"

namespace skypol::studies {

struct RaysBenchRow {
  std::string model;   // Lens::name()
  std::string source;  // where its parameters come from (a calibration file, a preset)
  int width = 0, height = 0;
  std::size_t inside = 0;         // pixels with a ray
  double base_mrays_per_s = 0;    // Lens::ray_row of the base class (ray() per pixel), best of n
  double row_mrays_per_s = 0;     // the model's ray_row, best of n
  double camera_mrays_per_s = 0;  // Camera::ray_row (the renderer's: rotation, polarizer, floats), best of n
  double max_round_trip_px = 0;   // max |project(ray_row(p)) − p| over the pixels inside
  double max_vs_ray_rad = 0;      // max angle between ray_row(p) and ray(p)
  std::size_t valid_mismatches = 0;  // pixels where ray_row and ray() disagree on having a ray
  std::size_t project_failures = 0;  // ray_row directions that project() refuses
};

struct RaysBenchLens {
  std::string source;
  std::shared_ptr<const camera::Lens> lens;
};

// The lenses of scenes/calibrations/ (one per model there) and the SkyPole paper's equidistant
// lens, read relative to `scenes_dir` (the repository's scenes/).
std::vector<RaysBenchLens> rays_bench_lenses(const std::string& scenes_dir);

// Times every row of the sensor on one thread (its CPU time, best of `repeats`); the round trip and the
// agreement with ray() on every pixel.
RaysBenchRow bench_rays(const RaysBenchLens& lens, int repeats);

}  // namespace skypol::studies
