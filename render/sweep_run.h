// Running a sweep (scene/sweep.h says what a sweep file means): every variant checked before
// anything is written, the manifest, then this shard's stacks rendered through the pipeline.
// Runs resume (a variant whose file exists is done: stacks are renamed into place only when whole)
// and split with --shard i/N with no coordination between the runs.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "scene/sweep.h"

namespace skypol::render {

struct SweepOptions {
  std::string out_dir;
  scene::Shard shard;
  std::vector<scene::Override> overrides;  // --set: after [set], before the axes
  int threads = 0;                  // TBB threads per run; 0 = all cores
  bool dry_run = false;             // check every variant, write the manifest, count what is done
  std::function<void(const std::string&)> log;  // one line per variant (may be empty)
};

struct SweepReport {
  std::size_t variants = 0;  // in the whole sweep
  std::size_t in_shard = 0;
  std::size_t rendered = 0;
  std::size_t skipped = 0;   // already complete (also counted in a dry run)
  std::vector<std::string> failures;  // one message per variant that could not be written
  double check_seconds = 0;  // loading and checking every variant, and the manifest
  double render_seconds = 0;
};

// Checks every variant (a SceneError before anything is written), creates out_dir, writes
// out_dir/manifest.jsonl (every variant, whatever the shard: the same bytes from every run),
// then renders this shard's variants that are not complete. A variant that fails to render is
// reported in `failures` and the others go on.
SweepReport run_sweep(const scene::Sweep& sweep, const SweepOptions& options);

}  // namespace skypol::render
