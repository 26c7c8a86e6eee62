// The subcommands of `skypol`. Each registers itself on the CLI11 app; errors that a user can fix
// (scene, stack, arguments) are reported by main() as one line on stderr with exit code 2.
#pragma once

#include <CLI/CLI.hpp>

namespace skypol::cli {

void add_render(CLI::App& app);    // render + run
void add_info(CLI::App& app);
void add_sun(CLI::App& app);
void add_estimate(CLI::App& app);
void add_evaluate(CLI::App& app);
void add_lens(CLI::App& app);
void add_bench(CLI::App& app);
void add_sweep(CLI::App& app);
void add_bench_occluders(CLI::App& app);
void add_preview(CLI::App& app);
void add_reproduce(CLI::App& app);  // the papers in simulation (studies/reproduce.h)
void add_tradeoff(CLI::App& app);  // cli/cmd_tradeoff.cpp
void add_table(CLI::App& app);     // cli/cmd_table.cpp: the VRTE solver in the Coulson tables' normalisation

// Progress on stderr, only when stderr is a terminal and not --quiet.
struct Progress {
  bool enabled;
  void operator()(std::size_t done, std::size_t total) const;
};
Progress make_progress(bool quiet);

}  // namespace skypol::cli
