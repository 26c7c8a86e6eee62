// `skypol bench-occluders SCENE`: what the occlusion test costs on a scene's camera and occluders.
// Figures only; nothing here is a test.
#include <cstdio>
#include <ctime>

#include "cli/commands.h"
#include "studies/occluders_bench.h"

namespace skypol::cli {

void add_bench_occluders(CLI::App& app) {
  struct Args {
    std::string scene = "scenes/urban-canyon.toml";
    int repeats = 5;
  };
  auto a = std::make_shared<Args>();
  CLI::App* bench = app.add_subcommand("bench-occluders", "Measure the occlusion test (Embree) on a scene with occluders");
  bench->add_option("scene", a->scene, "Scene file with an [occluders] section (default: the urban canyon, full frame)");
  bench->add_option("-n,--repeats", a->repeats, "Passes to time (the best is reported)")->check(CLI::Range(1, 1000));
  bench->callback([a] {
    const scene::Scene scene = scene::load_scene(a->scene);
    const studies::OccluderBenchFigures b = studies::bench_occluders(scene, a->repeats);
    char date[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    std::printf("skypol bench-occluders  %s  %s  threads %d\n", a->scene.c_str(), date, b.threads);
    std::printf("frame                 %d x %d px, spp 1, %zu rays inside the image circle\n", b.width, b.height, b.rays);
    std::printf("occluders             %zu triangles, BVH built in %.1f ms; %.1f %% of the rays blocked\n", b.triangles,
                b.build_ms, 100 * b.occluded_fraction);
    std::printf("occlusion test        %8.1f ms/frame   %8.1f Mrays/s   (%.1f Mpix/s of the whole frame; best of %d)\n",
                b.trace_ms, b.mrays_per_s, b.frame_mpix_per_s, b.repeats);
    std::printf("  in CPU time         %8.1f ms/frame   %8.1f Mrays per CPU-second (all threads together)\n",
                b.trace_cpu_ms, b.mrays_per_cpu_s);
    std::printf("renderer ray set-up   %8.1f ms without occluders, %.1f ms with (once per stack)\n", b.setup_ms_without,
                b.setup_ms_with);
  });
}

}  // namespace skypol::cli
