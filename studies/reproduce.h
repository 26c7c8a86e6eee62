// `skypol reproduce`: the two papers' figures and tables recomputed in simulation, written as CSV
// files and float EXR images into one folder for scripts/reproduce to draw and tabulate
// (docs/reproduction.md is its output). Each half lists its files at the top of its .cpp.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace skypol::studies {

struct ReproduceOptions {
  std::string out_dir;
  bool small = false;  // the reduced run the tests use: coarse grids, same quantities
  std::string scene = "scenes/skypole-marseille.toml";  // the SkyPole set-up
  std::string sun2019_scene = "scenes/sun2019-hefei.toml";  // Sun et al.'s site, atmosphere, times
  bool quiet = false;    // no messages on stderr
  std::function<void(std::size_t, std::size_t)> progress;  // (done, total) of the long protocol; may be empty
};

void reproduce_sun2019(const ReproduceOptions& options);
void reproduce_skypole(const ReproduceOptions& options);
// The SkyPole set-up under the VRTE sky beside single scattering (studies/reproduce_vrte.cpp).
void reproduce_vrte(const ReproduceOptions& options);

// Writes `text` to dir/name under a temporary name, renamed when complete; returns the path.
std::string write_text(const std::string& dir, const std::string& name, const std::string& text);
// A number for a CSV field: shortest round-trip-safe form at 8 significant digits; "" if not finite.
std::string csv_num(double v);

}  // namespace skypol::studies
