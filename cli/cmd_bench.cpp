// `skypol bench SCENE`: what a frame costs. Figures only; nothing here is a test.
#include <cstdio>
#include <ctime>

#include "cli/commands.h"
#include "render/benchmark.h"

namespace skypol::cli {

void add_bench(CLI::App& app) {
  struct Args {
    std::string scene = "scenes/skypole-marseille.toml";
    int frames = 3;
    std::string scratch = "out/bench-scratch";
  };
  auto a = std::make_shared<Args>();
  CLI::App* bench = app.add_subcommand("bench", "Measure render and write throughput on a scene");
  bench->add_option("scene", a->scene, "Scene file (default: the SkyPole paper's, full resolution)");
  bench->add_option("-n,--frames", a->frames, "Frames to time")->check(CLI::Range(1, 1000));
  bench->add_option("--scratch", a->scratch, "Folder for temporary files (removed afterwards)");
  bench->callback([a] {
    const render::Scene scene = render::load_scene(a->scene);
    const render::BenchFigures b = render::bench_render(scene, a->frames, a->scratch);
    char date[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    std::printf("skypol bench  %s  %s  threads %d\n", a->scene.c_str(), date, b.threads);
    std::printf("frame                 %d x %d px, spp %d, %d frame(s), %.1f MB of pixels per frame\n", b.width,
                b.height, b.spp, b.frames, b.mb_per_frame);
    std::printf("camera rays (once)    %8.1f ms\n", 1e3 * b.ray_setup_s);
    std::printf("sky render            %8.1f ms/frame   %8.1f Mpix/s\n", b.frame_render_ms, b.sky_mpix_per_s);
    std::printf("OpenEXR alone write   %8.1f ms/frame\n", b.openexr_write_ms);
    std::printf("skypol stack write    %8.1f ms/frame   (%.2fx OpenEXR alone)\n", b.skypol_write_ms,
                b.skypol_write_ms / b.openexr_write_ms);
    std::printf("end to end            %8.1f ms/frame   (%.2fx OpenEXR alone)\n", b.end_to_end_ms,
                b.end_to_end_ms / b.openexr_write_ms);
  });
}

}  // namespace skypol::cli
