#include "studies/occluders_bench.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <limits>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "render/occluder_geometry.h"
#include "render/occluders_embree.h"
#include "render/occlusion_pass.h"
#include "render/renderer.h"

namespace skypol::studies {
namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
}  // namespace

OccluderBenchFigures bench_occluders(const scene::Scene& scene, int repeats) {
  if (scene.occluders.empty()) throw std::invalid_argument(scene.file + ": the scene has no [occluders] section");
  OccluderBenchFigures b;
  b.repeats = std::max(1, repeats);
  b.threads = tbb::this_task_arena::max_concurrency();
  const std::shared_ptr<const camera::Camera> cam = scene::build_camera(scene.camera);
  b.width = cam->width();
  b.height = cam->height();
  b.triangles = render::triangle_count(render::occluder_meshes(scene.occluders));

  auto t0 = Clock::now();
  const std::shared_ptr<const render::Occluders> occ = render::make_occluders(scene.occluders);
  b.build_ms = ms_since(t0);

  // The pixel centres' rays, as the renderer computes them at spp 1, in tiles of 16 rows.
  const int w = b.width, h = b.height, tile = 16;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<sky::ViewRay> rays(n);
  std::vector<float> sees(n);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      const std::optional<camera::CameraRay> r = cam->ray(Eigen::Vector2d(x, y));
      rays[i].d = r ? Eigen::Vector3f(r->d.cast<float>()) : Eigen::Vector3f::UnitZ();
      sees[i] = r ? 1.0f : 0.0f;
    }
  });
  b.rays = static_cast<std::size_t>(std::count(sees.begin(), sees.end(), 1.0f));

  std::vector<float> weight(n);
  double best = std::numeric_limits<double>::infinity();
  double best_cpu = best;
  for (int k = 0; k < b.repeats; ++k) {
    weight = sees;
    const std::clock_t c0 = std::clock();
    t0 = Clock::now();
    tbb::parallel_for(0, (h + tile - 1) / tile, [&](int t) {
      const std::size_t first = static_cast<std::size_t>(t * tile) * static_cast<std::size_t>(w);
      const std::size_t count = static_cast<std::size_t>(std::min(h, (t + 1) * tile) - t * tile) * static_cast<std::size_t>(w);
      render::apply_occluders(*occ, std::span<const sky::ViewRay>(rays).subspan(first, count), std::span(weight).subspan(first, count));
    });
    best = std::min(best, ms_since(t0));
    best_cpu = std::min(best_cpu, 1e3 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
  }
  b.trace_ms = best;
  b.trace_cpu_ms = best_cpu;
  b.mrays_per_cpu_s = static_cast<double>(b.rays) / (1e3 * best_cpu);
  b.mrays_per_s = static_cast<double>(b.rays) / (1e3 * best);
  b.frame_mpix_per_s = static_cast<double>(n) / (1e3 * best);
  const auto blocked = static_cast<std::size_t>(std::count(weight.begin(), weight.end(), 0.0f)) - (n - b.rays);
  b.occluded_fraction = b.rays ? static_cast<double>(blocked) / static_cast<double>(b.rays) : 0;

  // What the renderer's set-up costs per stack, with and without the occluders.
  render::RenderOptions ro;
  ro.channels = scene.output.channels;
  b.setup_ms_without = b.setup_ms_with = std::numeric_limits<double>::infinity();
  for (int k = 0; k < b.repeats; ++k) {
    t0 = Clock::now();
    { const render::Renderer r(cam, ro); }
    b.setup_ms_without = std::min(b.setup_ms_without, ms_since(t0));
    t0 = Clock::now();
    { const render::Renderer r(cam, ro, occ); }
    b.setup_ms_with = std::min(b.setup_ms_with, ms_since(t0));
  }
  return b;
}

}  // namespace skypol::studies
