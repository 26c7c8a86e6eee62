// The subcommands of `skypol`. Each registers itself on the CLI11 app; errors that a user can fix
// (scene, stack, arguments) are reported by main() as one line on stderr with exit code 2.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

namespace skypol::cli {

void add_render(CLI::App& app);    // render + run
void add_info(CLI::App& app);
void add_sun(CLI::App& app);
void add_estimate(CLI::App& app);
void add_evaluate(CLI::App& app);
void add_methods(CLI::App& app);   // cli/cmd_methods.cpp: the estimators' registry
void add_lens(CLI::App& app);
void add_bench(CLI::App& app);
// `skypol bench --rays`: the camera-ray table (cli/bench_rays.cpp); scenes_dir holds calibrations/.
void print_rays_bench(const std::string& scenes_dir, int repeats);
void add_sweep(CLI::App& app);
void add_bench_occluders(CLI::App& app);
void add_preview(CLI::App& app);
void add_reproduce(CLI::App& app);  // the papers in simulation (studies/reproduce.h)
void add_tradeoff(CLI::App& app);  // cli/cmd_tradeoff.cpp
void add_table(CLI::App& app);     // cli/cmd_table.cpp: the VRTE solver in the Coulson tables' normalisation

void add_import(CLI::App& app);     // cli/cmd_import.cpp: real captures into a stack
void add_export(CLI::App& app);     // cli/cmd_export.cpp: a stack's frames as single-part files

// "0.1.0 (git v0.1-123-gabcdef)": CMake's project version and, when the tree was a git checkout
// at configure time, git describe's answer.
std::string version_text();

// Progress on stderr, only when stderr is a terminal and not --quiet: a bar, the count, the rate
// and the time left (cli/progress.cpp), redrawn at most ten times a second.
struct Progress {
  bool enabled = false;
  const char* unit = "frames";
  std::chrono::steady_clock::time_point start;
  mutable double last_drawn_s = -1;
  void operator()(std::size_t done, std::size_t total) const;
};
Progress make_progress(bool quiet, const char* unit = "frames");
// A Progress that also redraws itself twice a second between calls, so that one long step (an
// estimate of a single method) still shows the time passing. Nothing when the Progress is disabled.
class Ticker {
 public:
  explicit Ticker(Progress p);
  ~Ticker();  // draws the last state and stops
  void operator()(std::size_t done, std::size_t total);
  // Erases the line until the next call, for output that goes to the same terminal.
  void hide();
  Ticker(const Ticker&) = delete;
  Ticker& operator=(const Ticker&) = delete;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The line drawn: "[####      ] 3/10 frames, 1.5/s, 5 s left" (done = total: the time taken).
std::string progress_line(std::size_t done, std::size_t total, double elapsed_s, const char* unit);

}  // namespace skypol::cli
