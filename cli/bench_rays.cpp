// `skypol bench --rays`: one line per lens model (studies/rays_bench.h).
#include <cstdio>
#include <filesystem>

#include "cli/commands.h"
#include "studies/benchmark.h"
#include "studies/rays_bench.h"

namespace skypol::cli {

void print_rays_bench(const std::string& scenes_dir, int repeats) {
  const studies::BenchContext c = studies::bench_context();
  std::printf("skypol bench --rays  %s  load average %.2f  %s, %s  one thread, CPU time, best of %d full frames\n",
              c.date_utc.c_str(), c.load_average, c.build_type.c_str(), c.compiler.c_str(), repeats);
  std::printf("%-18s %-11s %9s %11s %11s %8s %13s %14s %14s %s\n", "model", "sensor", "inside", "ray() Mr/s",
              "row Mr/s", "speed-up", "camera Mr/s", "round trip px", "vs ray() rad", "parameters from");
  const std::string dir = scenes_dir.empty() ? "." : scenes_dir;
  for (const auto& lens : studies::rays_bench_lenses(dir)) {
    const studies::RaysBenchRow r = studies::bench_rays(lens, repeats);
    char sensor[32];
    std::snprintf(sensor, sizeof sensor, "%dx%d", r.width, r.height);
    std::printf("%-18s %-11s %9zu %11.1f %11.1f %7.2fx %13.1f %14.2e %14.2e %s", r.model.c_str(), sensor, r.inside,
                r.base_mrays_per_s, r.row_mrays_per_s, r.row_mrays_per_s / r.base_mrays_per_s, r.camera_mrays_per_s,
                r.max_round_trip_px, r.max_vs_ray_rad, r.source.c_str());
    if (r.valid_mismatches) std::printf("  (%zu pixels: ray_row and ray() disagree on validity)", r.valid_mismatches);
    if (r.project_failures) std::printf("  (%zu rays that project() refuses)", r.project_failures);
    std::printf("\n");
  }
}

}  // namespace skypol::cli
