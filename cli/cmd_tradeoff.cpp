// `skypol tradeoff STUDY --out DIR [--small]`: what accuracy costs in time, measured by calling the
// libraries directly (studies/tradeoff_studies.h). Writes CSV tables and meta.csv (how they were
// made); scripts/benchmarks turns them into docs/benchmarks.md and its plots.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <stdexcept>

#include <tbb/info.h>

#include "cli/commands.h"
#include "skypole/evaluate.h"
#include "studies/tradeoff_studies.h"
#include "studies/tradeoff_table.h"

namespace skypol::cli {
namespace {

std::string utc_now() {
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return date;
}

// How the figures were made, beside them: the report quotes it.
void write_meta(const studies::tradeoff::StudyOptions& o, const std::string& which, double seconds) {
  studies::tradeoff::Table meta({"key", "value"});
  meta.row().set("key", "date_utc").set("value", utc_now());
  meta.row().set("key", "studies").set("value", which);
  meta.row().set("key", "small").set("value", o.small);
  meta.row().set("key", "seed").set("value", static_cast<int>(o.seed));
  meta.row().set("key", "count").set("value", o.count);
  meta.row().set("key", "binning").set("value", o.binning);
  meta.row().set("key", "uncalibrated").set("value", o.uncalibrated);
  meta.row().set("key", "no_cloud_gate").set("value", o.no_cloud_gate);
  meta.row().set("key", "no_sky_mask").set("value", o.no_sky_mask);
  meta.row().set("key", "noise_draw").set("value", o.noise_draw);
  meta.row().set("key", "population").set("value", o.population);
  std::string methods;
  for (const std::string& m : o.methods) methods += (methods.empty() ? "" : ",") + m;
  meta.row().set("key", "methods").set("value", methods.empty() ? std::string("all") : methods);
  meta.row().set("key", "threads").set("value", tbb::info::default_concurrency());
  meta.row().set("key", "compiler").set("value", std::string("GCC ") + __VERSION__);
#ifdef __OPTIMIZE__
  meta.row().set("key", "optimized").set("value", 1);
#else
  meta.row().set("key", "optimized").set("value", 0);
#endif
#ifdef NDEBUG
  meta.row().set("key", "assertions").set("value", "off");
#else
  meta.row().set("key", "assertions").set("value", "on");
#endif
  meta.row().set("key", "seconds").set("value", seconds);
  meta.write((std::filesystem::path(o.out_dir) / "meta.csv").string());
}

}  // namespace

void add_tradeoff(CLI::App& app) {
  struct Args {
    std::string study;
    studies::tradeoff::StudyOptions options;
  };
  auto a = std::make_shared<Args>();
  std::string names = "all";
  for (const studies::tradeoff::Study& s : studies::tradeoff::studies()) names += ", " + s.name;
  std::string help = "Study to run: " + names;
  CLI::App* cmd = app.add_subcommand(
      "tradeoff", "Measure what accuracy costs in time (CSV tables; scripts/benchmarks plots them)");
  cmd->add_option("study", a->study, help)->required();
  cmd->add_option("--out", a->options.out_dir, "Folder for the CSV files")->required();
  cmd->add_flag("--small", a->options.small, "Tiny images and few settings (seconds; for tests)");
  cmd->add_option("--seed", a->options.seed, "calibration: seed of the random scenes (default 2)");
  cmd->add_option("--count", a->options.count, "calibration: number of scenes (default 300; --small 6)");
  cmd->add_option("--binning", a->options.binning, "calibration, compression: binning of the 2448×2048 sensor (calibration 8, compression 4; --small 16)");
  cmd->add_option("--max-uncertainty", a->options.max_uncertainty_deg,
                  "calibration: the bound every method runs with (95 % cone, degrees; default 2.5, i.e. σ ≤ 1.02°, so that 5° off is 5σ; inf: none)");
  cmd->add_flag("--progress", a->options.progress, "calibration: report each scene on stderr");
  cmd->add_flag("--uncalibrated", a->options.uncalibrated,
                "calibration: σ without the methods' calibration factors (to measure them)");
  cmd->add_flag("--no-cloud-gate", a->options.no_cloud_gate,
                "calibration: without the whole-sky cloud gate (skypole/cloud_share.h)");
  cmd->add_flag("--no-sky-mask", a->options.no_sky_mask,
                "calibration: the methods fit every sky pixel (no per-pixel mask, skypole/sky_mask.h)");
  cmd->add_option("--methods", a->options.methods,
                  "calibration: run only these methods, comma-separated (and auto over them; default: every method)")
      ->delimiter(',');
  cmd->add_option("--scenes", a->options.scenes,
                  "calibration: run only these scenes of the seeded population, comma-separated indices (the CSV's "
                  "`stack` column; default: all), the same scenes as in the whole run")
      ->delimiter(',');
  cmd->add_option("--population", a->options.population,
                  "calibration: mixed (default: Rayleigh and Berry in 70 % of the scenes, 12 vrte atmospheres), "
                  "realistic (vrte in 70 %, every OPAC aerosol, tau(550) 0.02-0.8 log-uniform, albedo 0-0.35) or "
                  "mismatch (outside the calibration's families: custom aerosol modes, other vrte streams and grids, "
                  "other Berry skies, tilted cameras, sensors with polarizer angle errors, extinction ratio, PRNU, DSNU)")
      ->check(CLI::IsMember({"mixed", "realistic", "mismatch"}));
  cmd->add_option("--noise-draw", a->options.noise_draw,
                  "calibration: the sensor's noise draw (0: each scene's own; k > 0: new noise for the same scenes, "
                  "their noise replicates)")
      ->check(CLI::Range(0, 1000000));
  cmd->callback([a] {
    std::vector<const studies::tradeoff::Study*> run;
    for (const studies::tradeoff::Study& s : studies::tradeoff::studies())
      if (a->study == "all" || a->study == s.name) run.push_back(&s);
    if (run.empty()) {
      std::string legal = "all";
      for (const studies::tradeoff::Study& s : studies::tradeoff::studies()) legal += ", " + s.name;
      throw std::invalid_argument("tradeoff: unknown study \"" + a->study + "\" (expected one of " + legal + ")");
    }
    for (const std::string& m : a->options.methods) {
      const auto& legal_names = skypole::method_names();
      if (m == "auto" || std::find(legal_names.begin(), legal_names.end(), m) == legal_names.end()) {
        std::string legal;
        for (const std::string& n : legal_names)
          if (n != "auto") legal += (legal.empty() ? "" : ", ") + n;
        throw std::invalid_argument("tradeoff: --methods: unknown method \"" + m + "\" (expected one of " + legal +
                                    "; auto always runs)");
      }
    }
    if (a->study == "all" || a->study == "calibration") studies::tradeoff::check_calibration_scenes(a->options);
    std::filesystem::create_directories(a->options.out_dir);
    const auto t0 = std::chrono::steady_clock::now();
    for (const studies::tradeoff::Study* s : run) {
      const double sec = studies::tradeoff::best_seconds(1, [&] { s->run(a->options); });
      std::fprintf(stderr, "tradeoff %-14s %7.1f s  -> %s/%s.csv\n", s->name.c_str(), sec,
                   a->options.out_dir.c_str(), s->name.c_str());
    }
    write_meta(a->options, a->study,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  });
}

}  // namespace skypol::cli
