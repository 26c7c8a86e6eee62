// `skypol reproduce {sun2019|skypole|all} --out DIR [--small]` (cli/reproduce.h).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "cli/commands.h"
#include "cli/reproduce.h"

namespace skypol::cli {

std::string write_text(const std::string& dir, const std::string& name, const std::string& text) {
  const std::filesystem::path path = std::filesystem::path(dir) / name;
  const std::string tmp = path.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    if (!f) {
      std::remove(tmp.c_str());
      throw std::runtime_error("cannot write " + path.string());
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write " + path.string() + ": " + ec.message());
  }
  return path.string();
}

std::string csv_num(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream os;
  os << std::setprecision(8) << v;
  return os.str();
}

void add_reproduce(CLI::App& app) {
  struct Args {
    std::string which;
    ReproduceOptions options;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "reproduce", "Recompute the papers' figures and tables in simulation (data for scripts/reproduce)");
  cmd->add_option("which", a->which, "sun2019 | skypole | all")
      ->required()
      ->check(CLI::IsMember({"sun2019", "skypole", "all"}));
  cmd->add_option("-o,--out", a->options.out_dir, "Folder for the CSV and EXR files")->required();
  cmd->add_flag("--small", a->options.small, "Reduced run (coarse grids), as the tests use");
  cmd->add_option("--scene", a->options.scene, "The SkyPole set-up (site, day, times, camera)");
  cmd->add_option("--sun2019-scene", a->options.sun2019_scene,
                  "Sun et al.'s set-up (site, atmosphere, the times of their Table 1)");
  cmd->add_flag("-q,--quiet", a->options.quiet, "No progress on stderr");
  cmd->callback([a] {
    std::error_code ec;
    std::filesystem::create_directories(a->options.out_dir, ec);
    if (ec || !std::filesystem::is_directory(a->options.out_dir))
      throw std::invalid_argument("reproduce: cannot create the output folder " + a->options.out_dir +
                                  (ec ? ": " + ec.message() : std::string()));
    const auto t0 = std::chrono::steady_clock::now();
    auto t1 = t0;
    try {
      if (a->which == "sun2019" || a->which == "all") reproduce_sun2019(a->options);
      t1 = std::chrono::steady_clock::now();
      if (a->which == "skypole" || a->which == "all") reproduce_skypole(a->options);
    } catch (const std::runtime_error& e) {  // I/O (filesystem_error too): the user can fix it
      throw std::invalid_argument(std::string("reproduce: ") + e.what());
    }
    const auto t2 = std::chrono::steady_clock::now();
    std::printf("reproduce: sun2019 %.1f s, skypole %.1f s, into %s\n",
                std::chrono::duration<double>(t1 - t0).count(),
                std::chrono::duration<double>(t2 - t1).count(), a->options.out_dir.c_str());
  });
}

}  // namespace skypol::cli
