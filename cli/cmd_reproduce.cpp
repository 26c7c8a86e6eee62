// `skypol reproduce {sun2019|skypole|all} --out DIR [--small]` (studies/reproduce.h).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "cli/commands.h"
#include "studies/reproduce.h"

namespace skypol::cli {

void add_reproduce(CLI::App& app) {
  struct Args {
    std::string which;
    studies::ReproduceOptions options;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "reproduce", "Recompute the papers' figures and tables in simulation (data for scripts/reproduce)");
  cmd->add_option("which", a->which, "sun2019 | skypole | vrte | all")
      ->required()
      ->check(CLI::IsMember({"sun2019", "skypole", "vrte", "all"}));
  cmd->add_option("-o,--out", a->options.out_dir, "Folder for the CSV and EXR files")->required();
  cmd->add_flag("--small", a->options.small, "Reduced run (coarse grids), as the tests use");
  cmd->add_option("--scene", a->options.scene, "The SkyPole set-up (site, day, times, camera)");
  cmd->add_option("--sun2019-scene", a->options.sun2019_scene,
                  "Sun et al.'s set-up (site, atmosphere, the times of their Table 1)");
  cmd->add_flag("-q,--quiet", a->options.quiet, "No progress on stderr");
  cmd->callback([a] {
    a->options.progress = make_progress(a->options.quiet);
    std::error_code ec;
    std::filesystem::create_directories(a->options.out_dir, ec);
    if (ec || !std::filesystem::is_directory(a->options.out_dir))
      throw std::invalid_argument("reproduce: cannot create the output folder " + a->options.out_dir +
                                  (ec ? ": " + ec.message() : std::string()));
    const auto t0 = std::chrono::steady_clock::now();
    auto t1 = t0;
    try {
      if (a->which == "sun2019" || a->which == "all") studies::reproduce_sun2019(a->options);
      t1 = std::chrono::steady_clock::now();
      if (a->which == "skypole" || a->which == "all") studies::reproduce_skypole(a->options);
    } catch (const std::runtime_error& e) {  // I/O (filesystem_error too): the user can fix it
      throw std::invalid_argument(std::string("reproduce: ") + e.what());
    }
    const auto t2 = std::chrono::steady_clock::now();
    try {
      if (a->which == "vrte" || a->which == "all") studies::reproduce_vrte(a->options);
    } catch (const std::runtime_error& e) {  // I/O (filesystem_error too): the user can fix it
      throw std::invalid_argument(std::string("reproduce: ") + e.what());
    }
    const auto t3 = std::chrono::steady_clock::now();
    std::printf("reproduce: sun2019 %.1f s, skypole %.1f s, vrte %.1f s, into %s\n",
                std::chrono::duration<double>(t1 - t0).count(), std::chrono::duration<double>(t2 - t1).count(),
                std::chrono::duration<double>(t3 - t2).count(), a->options.out_dir.c_str());
  });
}

}  // namespace skypol::cli
