// `skypol bench SCENE`: what a frame costs. Figures only; nothing here is a test.
// --json prints the same figures and their context as one JSON object, for scripts.
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "studies/benchmark.h"
#include "studies/vrte_bench.h"
#include "scene/json_text.h"

namespace skypol::cli {
namespace {

using scene::json_quoted;

void print_text(const std::string& scene, const studies::BenchFigures& b) {
  const studies::BenchContext& c = b.context;
  std::printf("skypol bench  %s  %s\n", scene.c_str(), c.date_utc.c_str());
  std::printf("machine               %s, %d hardware threads (renderer uses %d), load average %.2f\n", c.cpu.c_str(),
              c.hardware_threads, c.tbb_threads, c.load_average);
  std::printf("build                 %s, %s\n", c.build_type.c_str(), c.compiler.c_str());
  std::printf("frame                 %d x %d px, spp %d, %d frame(s), %zu channels, %s%s, %.1f MB of pixels per frame\n",
              b.width, b.height, b.spp, b.frames, b.channels.size(), b.compression.c_str(), b.half ? ", half" : "",
              b.mb_per_frame);
  std::printf("camera rays (once)    %8.1f ms\n", b.ray_setup_ms);
  std::printf("frame memory (once)   %8.1f ms\n", b.frame_alloc_ms);
  std::printf("sky render            %8.1f ms/frame   %8.1f Mpix/s   (best frame %.1f ms, %.1f Mpix/s)\n",
              b.frame_render_ms, b.sky_mpix_per_s, b.frame_render_best_ms, b.sky_mpix_per_s_best);
  std::printf("  into a new frame    %8.1f ms/frame   (allocation and first-touch page faults included)\n",
              b.fresh_frame_render_ms);
  if (b.openexr_write_ms == 0) return;  // --render-only
  std::printf("OpenEXR alone write   %8.1f ms/frame                       (best frame %.1f ms)\n", b.openexr_write_ms,
              b.openexr_write_best_ms);
  std::printf("skypol stack write    %8.1f ms/frame   (%.2fx OpenEXR alone)   (best frame %.1f ms, %.2fx)\n",
              b.skypol_write_ms, b.skypol_write_ms / b.openexr_write_ms, b.skypol_write_best_ms,
              b.skypol_write_best_ms / b.openexr_write_best_ms);
  std::printf("render + write, best  %8.1f ms/frame   (%.2fx OpenEXR alone's best)\n", b.render_and_write_best_ms,
              b.render_and_write_best_ms / b.openexr_write_best_ms);
  std::printf("end to end            %8.1f ms/frame   (%.2fx OpenEXR alone)   (skypol's pipeline, wall)\n",
              b.end_to_end_ms, b.end_to_end_ms / b.openexr_write_ms);
  if (b.zip_levels.empty()) return;
  std::printf("zip level (OpenEXR alone, one frame, best of 3; %s pixels)\n", b.half ? "half" : "float");
  std::printf("  level   write (ms)   size (MB)   ratio to raw\n");
  for (const auto& z : b.zip_levels)
    std::printf("  %5d   %10.1f   %9.2f   %12.3f\n", z.level, z.write_ms, z.mb, z.mb / b.mb_per_frame);
}

void print_vrte_text(const studies::VrteBenchFigures& v) {
  std::printf("vrte sky              %s aerosol, tau(550) %.3g, %d streams, grid %d, solver on %d threads\n",
              v.aerosol.c_str(), v.tau_550, v.streams, v.grid, v.solver_threads);
  for (std::size_t i = 0; i < v.bands.size(); ++i) {
    std::printf("  table %-3s %5.0f nm  %8.3f s to build (cold)   %8.1f ms to read (warm)\n", v.bands[i].c_str(),
                v.wavelengths_nm[i], v.cold_build_s[i], 1e3 * v.warm_read_s[i]);
  }
  std::printf("  sky render          %8.1f ms/frame single scattering, %8.1f vrte (%.2fx)   (best %.1f, %.1f: %.2fx)\n",
              v.single_render_ms, v.vrte_render_ms, v.vrte_render_ms / v.single_render_ms, v.single_render_best_ms,
              v.vrte_render_best_ms, v.vrte_render_best_ms / v.single_render_best_ms);
  std::printf("  sky render, CPU     %8.1f ms/frame single scattering, %8.1f vrte (%.2fx)   (all threads' CPU time)\n",
              v.single_render_cpu_ms, v.vrte_render_cpu_ms, v.vrte_render_cpu_ms / v.single_render_cpu_ms);
  std::printf("  render + write      %8.1f ms/frame single scattering, %8.1f vrte (%.2fx)   (render_scene, warm tables)\n",
              v.single_end_to_end_ms, v.vrte_end_to_end_ms, v.vrte_end_to_end_ms / v.single_end_to_end_ms);
  for (std::size_t i = 0; i < v.sweep_streams.size(); ++i) {
    std::printf("  streams %-3d         %8.3f s to build the %s table\n", v.sweep_streams[i], v.sweep_build_s[i],
                v.bands.front().c_str());
  }
}

std::string vrte_json(const studies::VrteBenchFigures& v) {
  auto list = [](const std::vector<double>& x) {
    std::string s;
    char buf[32];
    for (double d : x) {
      std::snprintf(buf, sizeof buf, "%.4f", d);
      s += (s.empty() ? "" : ", ") + std::string(buf);
    }
    return "[" + s + "]";
  };
  std::string bands;
  for (const std::string& b : v.bands) bands += (bands.empty() ? "" : ", ") + scene::json_quoted(b);
  std::string streams;
  for (int n : v.sweep_streams) streams += (streams.empty() ? "" : ", ") + std::to_string(n);
  char buf[2048];
  std::snprintf(buf, sizeof buf,
                ",\n \"vrte\": {\"aerosol\": %s, \"tau_550\": %.4g, \"streams\": %d, \"grid\": %d, \"solver_threads\": %d, "
                "\"bands\": [%s], \"wavelengths_nm\": %s, \"cold_build_s\": %s, \"warm_read_s\": %s,\n"
                "  \"single_render_ms\": %.3f, \"vrte_render_ms\": %.3f, \"single_render_best_ms\": %.3f, "
                "\"vrte_render_best_ms\": %.3f, \"single_render_cpu_ms\": %.3f, \"vrte_render_cpu_ms\": %.3f, "
                "\"single_end_to_end_ms\": %.3f, \"vrte_end_to_end_ms\": %.3f, "
                "\"end_to_end_vrte_vs_single\": %.4f, \"sweep_streams\": [%s], \"sweep_build_s\": %s}",
                scene::json_quoted(v.aerosol).c_str(), v.tau_550, v.streams, v.grid, v.solver_threads, bands.c_str(),
                list(v.wavelengths_nm).c_str(), list(v.cold_build_s).c_str(), list(v.warm_read_s).c_str(),
                v.single_render_ms, v.vrte_render_ms, v.single_render_best_ms, v.vrte_render_best_ms,
                v.single_render_cpu_ms, v.vrte_render_cpu_ms, v.single_end_to_end_ms, v.vrte_end_to_end_ms, v.vrte_end_to_end_ms / v.single_end_to_end_ms,
                streams.c_str(), list(v.sweep_build_s).c_str());
  return buf;
}

void print_json(const std::string& scene, const studies::BenchFigures& b, const std::string& extra) {
  const studies::BenchContext& c = b.context;
  std::string channels;
  for (const std::string& ch : b.channels) channels += (channels.empty() ? "" : ", ") + scene::json_quoted(ch);
  std::printf("{\"scene\": %s, \"date_utc\": %s,\n", scene::json_quoted(scene).c_str(), scene::json_quoted(c.date_utc).c_str());
  std::printf(" \"machine\": {\"cpu\": %s, \"hardware_threads\": %d, \"renderer_threads\": %d, \"load_average\": %.2f},\n",
              scene::json_quoted(c.cpu).c_str(), c.hardware_threads, c.tbb_threads, c.load_average);
  std::printf(" \"build\": {\"type\": %s, \"compiler\": %s},\n", scene::json_quoted(c.build_type).c_str(), scene::json_quoted(c.compiler).c_str());
  std::printf(" \"frame\": {\"width\": %d, \"height\": %d, \"spp\": %d, \"frames\": %d, \"channels\": [%s], "
              "\"compression\": %s, \"half\": %s, \"mb_per_frame\": %.3f},\n",
              b.width, b.height, b.spp, b.frames, channels.c_str(), scene::json_quoted(b.compression).c_str(),
              b.half ? "true" : "false", b.mb_per_frame);
  std::printf(" \"ray_setup_ms\": %.3f, \"frame_alloc_ms\": %.3f,\n", b.ray_setup_ms, b.frame_alloc_ms);
  std::printf(" \"sky_render_ms_per_frame\": %.3f, \"sky_mpix_per_s\": %.3f, \"new_frame_render_ms\": %.3f,\n",
              b.frame_render_ms, b.sky_mpix_per_s, b.fresh_frame_render_ms);
  std::printf(" \"sky_render_best_ms\": %.3f, \"sky_mpix_per_s_best\": %.3f", b.frame_render_best_ms,
              b.sky_mpix_per_s_best);
  if (b.openexr_write_ms == 0) {  // --render-only
    std::printf("%s}\n", extra.c_str());
    return;
  }
  std::printf(",\n");
  std::printf(" \"openexr_write_ms_per_frame\": %.3f, \"openexr_write_best_ms\": %.3f,\n", b.openexr_write_ms,
              b.openexr_write_best_ms);
  std::printf(" \"skypol_write_ms_per_frame\": %.3f, \"skypol_write_best_ms\": %.3f, "
              "\"render_and_write_best_ms\": %.3f,\n",
              b.skypol_write_ms, b.skypol_write_best_ms, b.render_and_write_best_ms);
  std::printf(" \"end_to_end_ms_per_frame\": %.3f,\n", b.end_to_end_ms);
  std::string zips;
  char zbuf[128];
  for (const auto& z : b.zip_levels) {
    std::snprintf(zbuf, sizeof zbuf, "{\"level\": %d, \"write_ms\": %.3f, \"mb\": %.3f}", z.level, z.write_ms, z.mb);
    zips += (zips.empty() ? "" : ", ") + std::string(zbuf);
  }
  std::printf(" \"zip_levels\": [%s],\n", zips.c_str());
  std::printf(" \"skypol_write_vs_openexr\": %.4f, \"render_and_write_best_vs_openexr_best\": %.4f, "
              "\"end_to_end_vs_openexr\": %.4f%s}\n",
              b.skypol_write_ms / b.openexr_write_ms, b.render_and_write_best_ms / b.openexr_write_best_ms,
              b.end_to_end_ms / b.openexr_write_ms, extra.c_str());
}

}  // namespace

void add_bench(CLI::App& app) {
  struct Args {
    std::string scene = "scenes/skypole-marseille.toml";
    int frames = 3;
    std::string scratch = "out/bench-scratch";
    bool json = false;
    bool render_only = false;
    bool no_vrte = false;
    bool rays = false;
    std::vector<int> vrte_streams;
    std::vector<int> zip_levels;
  };
  auto a = std::make_shared<Args>();
  CLI::App* bench = app.add_subcommand("bench", "Measure render and write throughput on a scene");
  bench->add_option("scene", a->scene, "Scene file (default: the SkyPole paper's, full resolution)");
  bench->add_option("-n,--frames", a->frames, "Frames to time")->check(CLI::Range(1, 1000));
  bench->add_option("--scratch", a->scratch, "Folder for temporary files (removed afterwards)");
  bench->add_flag("--json", a->json, "Print the figures and their context as one JSON object");
  bench->add_flag("--render-only", a->render_only, "Time the renderer only (no writing, no end-to-end run)");
  bench->add_flag("--no-vrte", a->no_vrte,
                  "Skip the VRTE sky's figures (table build per band, warm-table render beside single scattering)");
  bench->add_flag("--rays", a->rays,
                  "Only the camera rays: Mrays/s per lens model (scenes/calibrations/) and the round trip in px");
  bench->add_option("--vrte-streams", a->vrte_streams,
                    "Also time the first band's VRTE table at each of these streams values (the accuracy knob)")
      ->check(CLI::Range(4, 64));
  bench->add_option("--zip-levels", a->zip_levels,
                    "Also time OpenEXR alone writing a frame with zip at each of these deflate levels (a table; "
                    "the scene's compression is unchanged)")
      ->check(CLI::Range(1, 9));
  bench->callback([a] {
    if (a->rays) return print_rays_bench(std::filesystem::path(a->scene).parent_path().string(), a->frames);
    const scene::Scene scene = scene::load_scene(a->scene);
    const studies::BenchFigures b = studies::bench_render(scene, a->frames, a->scratch, a->render_only, a->zip_levels);
    std::optional<studies::VrteBenchFigures> v;
    if (!a->no_vrte) v = studies::bench_vrte(scene, a->frames, a->scratch, a->vrte_streams);
    if (a->json) {
      print_json(a->scene, b, v ? vrte_json(*v) : "");
    } else {
      print_text(a->scene, b);
      if (v) print_vrte_text(*v);
    }
  });
}

}  // namespace skypol::cli
