// `skypol sweep SWEEP.toml -o DIR [--shard i/N]`: one stack per variant of a grid over a base
// scene, a manifest, resume, and shards for job runners (docs/datasets.md).
#include <cstdio>
#include <stdexcept>

#include "cli/commands.h"
#include "render/sweep_run.h"

namespace skypol::cli {

void add_sweep(CLI::App& app) {
  struct Args {
    std::string sweep;
    std::string out;
    std::string shard = "1/1";
    std::vector<std::string> set;
    int threads = 0;
    bool dry_run = false;
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("sweep", "Render every variant of a sweep (a base scene and a grid of keys) "
                                                "into a folder, with a manifest; resumes, and splits into shards");
  cmd->add_option("sweep", a->sweep, "Sweep file (TOML, docs/datasets.md)")->required();
  cmd->add_option("-o,--output", a->out, "Output folder (stacks and manifest.jsonl)")->required();
  cmd->add_option("--shard", a->shard, "Render only shard i of N (1 <= i <= N): variants k with k mod N = i-1");
  cmd->add_option("--set", a->set, "Override a scene key in every variant (not an axis; repeatable)")
      ->allow_extra_args(false);
  cmd->add_option("-j,--threads", a->threads, "Threads per run (default: all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("-n,--dry-run", a->dry_run, "Check every variant and write the manifest; render nothing");
  cmd->add_flag("-q,--quiet", a->quiet, "No line per variant on stderr");
  cmd->callback([a] {
    render::SweepOptions o;
    o.out_dir = a->out;
    o.shard = scene::parse_shard(a->shard);  // before anything is read or written
    for (const std::string& s : a->set) o.overrides.push_back(scene::parse_override(s));
    o.threads = a->threads;
    o.dry_run = a->dry_run;
    const scene::Sweep sweep = scene::load_sweep(a->sweep);
    // On a terminal, a progress line under the variants' lines: variants of this shard done, their
    // rate and the time left (those already complete count as done when the run ends).
    std::size_t in_shard = 0, logged = 0;
    for (std::size_t i = 0; i < sweep.size(); ++i) in_shard += o.shard.has(i) ? 1 : 0;
    auto ticker = std::make_shared<Ticker>(make_progress(a->quiet || a->dry_run, "variants"));
    if (!a->quiet) {
      o.log = [ticker, &logged, in_shard](const std::string& line) {
        ticker->hide();
        std::fprintf(stderr, "%s\n", line.c_str());
        ++logged;
        if (logged < in_shard) (*ticker)(logged, in_shard);
      };
      (*ticker)(0, in_shard);
    }
    const render::SweepReport r = render::run_sweep(sweep, o);
    ticker->hide();
    ticker.reset();
    if (!a->quiet && o.dry_run) {
      std::fprintf(stderr, "sweep %s (dry run): %zu variant(s) checked in %.2f s, manifest written; shard %zu/%zu has %zu: "
                   "%zu complete, %zu to render\n", a->sweep.c_str(), r.variants, r.check_seconds, o.shard.index,
                   o.shard.count, r.in_shard, r.skipped, r.in_shard - r.skipped);
    } else if (!a->quiet) {
      std::fprintf(stderr,
                   "sweep %s: %zu variant(s), shard %zu/%zu has %zu: %zu rendered, %zu already complete, %zu failed "
                   "(checking %.2f s, rendering %.2f s)\n",
                   a->sweep.c_str(), r.variants, o.shard.index, o.shard.count, r.in_shard, r.rendered, r.skipped,
                   r.failures.size(), r.check_seconds, r.render_seconds);
    }
    if (!r.failures.empty()) {
      throw std::invalid_argument(std::to_string(r.failures.size()) + " variant(s) failed; the first: " +
                                  r.failures.front());
    }
  });
}

}  // namespace skypol::cli
