// `skypol evaluate DATASET…`: every method on every stack, scored into a CSV and a summary table
// (mean, median, 95th percentile and maximum of each error, per method; skypole/evaluate.h).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "cli/commands.h"
#include "skypole/report.h"
#include "scene/scene_error.h"
#include "stack/stack_io.h"
#include "skypole/evaluate.h"

namespace skypol::cli {
namespace {

namespace fs = std::filesystem;

// Stacks named on the command line: files as given, folders searched recursively for *.exr,
// sorted so that the CSV's row order does not depend on the file system. In folders, EXR files
// that are not skypol stacks (e.g. classic intermediates) are skipped with a note on stderr.
std::vector<std::string> find_stacks(const std::vector<std::string>& inputs) {
  std::vector<std::string> stacks;
  for (const std::string& in : inputs) {
    if (fs::is_directory(in)) {
      std::vector<std::string> found;
      for (const auto& entry : fs::recursive_directory_iterator(in)) {
        if (!entry.is_regular_file() || entry.path().extension() != ".exr") continue;
        try {
          if (!stack::peek_stack(entry.path().string()).truth_known) {
            std::fprintf(stderr, "skipped: %s: an imported capture, its truth unknown: nothing to score "
                                 "(skypol estimate gives its estimates)\n", entry.path().string().c_str());
            continue;
          }
          found.push_back(entry.path().string());
        } catch (const scene::SceneError& e) {
          std::fprintf(stderr, "skipped: %s\n", e.what());
        }
      }
      std::sort(found.begin(), found.end());
      if (found.empty()) throw std::invalid_argument(in + ": no .exr stacks with a truth to score in this folder");
      stacks.insert(stacks.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(in)) {
      if (!stack::peek_stack(in).truth_known) {
        throw std::invalid_argument(in + ": an imported capture, its truth unknown: evaluate has nothing to score "
                                         "against (skypol estimate gives its estimates)");
      }
      stacks.push_back(in);
    } else {
      throw std::invalid_argument(in + ": no such file or folder");
    }
  }
  return stacks;
}

// Written whole or not at all.
void write_text(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) {
      std::remove(tmp.c_str());
      throw std::invalid_argument("cannot write " + path);
    }
  }
  fs::rename(tmp, path);
}

}  // namespace

void add_evaluate(CLI::App& app) {
  struct Args {
    std::vector<std::string> inputs;
    std::vector<std::string> methods{"all"};
    std::string rows_csv, summary_csv;
    skypole::InputOptions input;
    std::string hemisphere = "automatic";
    std::string site = "stack";
    std::string polarizer_model = "stack";
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* ev = app.add_subcommand("evaluate", "Score estimators on many stacks: a CSV and a summary table");
  ev->add_option("dataset", a->inputs, "Stacks, or folders searched recursively for *.exr")->required();
  ev->add_option("-m,--method", a->methods,
                 "Estimators (" + skypole::method_names_list() + ": comma-separated, or all; default all)")
      ->delimiter(',');
  ev->add_option("--csv", a->rows_csv, "Write one row per (stack, method) to this CSV");
  ev->add_option("--summary", a->summary_csv, "Write the per-method summary to this CSV");
  ev->add_option("--band", a->input.band, "Band whose DoLP is used (default: B if present, else the first)");
  ev->add_option("--hemisphere", a->hemisphere, "automatic, north or south");
  ev->add_option("--site", a->site, skypole::kSiteOptionHelp);
  ev->add_option("--polarizer-model", a->polarizer_model, skypole::kPolarizerModelHelp);
  ev->add_option("--max-uncertainty", a->input.max_uncertainty_deg,
                  "Largest 95 % cone (degrees) an answer may have; a method whose stated uncertainty is "
                  "wider declines and says so (default: no bound)");
  ev->add_flag("-q,--quiet", a->quiet, "No per-stack progress on stderr");
  ev->callback([a] {
    a->input.hemisphere = skypole::parse_hemisphere(a->hemisphere);
    a->input.use_site = skypole::parse_site_use(a->site);
    a->input.polarizer_model = skypole::parse_polarizer_model(a->polarizer_model);
    const std::vector<std::string> methods = skypole::expand_methods(a->methods);
    const std::vector<std::string> stacks = find_stacks(a->inputs);
    std::vector<skypole::EvaluationRow> rows;
    for (std::size_t i = 0; i < stacks.size(); ++i) {
      const stack::Stack stack = stack::read_stack(stacks[i], skypole::estimator_channels(stacks[i], a->input));
      if (stack.frames.empty()) throw std::invalid_argument(stacks[i] + ": the stack has no frames");
      std::vector<skypole::PoleEstimate> done;  // auto combines these instead of running them again
      for (const std::string& m : methods) {
        skypole::EvaluationRow row;
        row.dataset = stacks[i];
        row.truth = stack.frames[0].truth;
        try {
          row.estimate = skypole::run_or_combine(stack, m, a->input, done);
        } catch (const std::invalid_argument& e) {
          // Input this method cannot use (too few frames, …): counted as invalid, with the reason.
          row.estimate.method = m;
          row.estimate.valid = false;
          row.estimate.why_invalid = e.what();
        }
        done.push_back(row.estimate);
        rows.push_back(std::move(row));
      }
      if (!a->quiet) std::fprintf(stderr, "[%zu/%zu] %s\n", i + 1, stacks.size(), stacks[i].c_str());
    }
    const std::vector<skypole::MethodSummary> summary = skypole::summarize(rows);
    if (!a->rows_csv.empty()) write_text(a->rows_csv, skypole::rows_csv(rows));
    if (!a->summary_csv.empty()) write_text(a->summary_csv, skypole::summary_csv(summary));
    std::printf("%zu stack(s), %zu method(s)\n%s", stacks.size(), methods.size(),
                skypole::summary_text(summary).c_str());
  });
}

}  // namespace skypol::cli
