// `skypol estimate STACK`: north from a stack, scored against the truth in its headers
// (skypole/report.h prints it).
#include <memory>
#include <string>

#include "cli/commands.h"
#include "skypole/evaluate.h"
#include "skypole/report.h"

namespace skypol::cli {

void add_estimate(CLI::App& app) {
  struct Args {
    skypole::EstimateRequest request;
    std::string hemisphere = "automatic";
    std::string site = "stack";
    std::string polarizer_model = "stack";
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  const std::string names = skypole::method_names_list();
  CLI::App* est = app.add_subcommand("estimate", "Estimate north and latitude on a stack; score against its truth");
  est->add_option("stack", a->request.path, "A stack written by skypol render")->required();
  est->add_option("-m,--method", a->request.methods, "Estimators (" + names + ", or all; `skypol methods` describes them); default classic")
      ->delimiter(',');
  est->add_option("--band", a->request.input.band, "Band whose DoLP is used (default: B if present, else the first)");
  est->add_option("--hemisphere", a->hemisphere, "automatic, north or south (the observer's, if known)");
  est->add_option("--site", a->site, skypole::kSiteOptionHelp);
  est->add_option("--polarizer-model", a->polarizer_model, skypole::kPolarizerModelHelp);
  est->add_option("--min-elevation", a->request.input.min_elevation_deg,
                  "Pixels lower than this (degrees, level frame) are ground and not used");
  est->add_option("--intermediates", a->request.intermediates,
                  "classic: write the step images (filtered, differences, binaries, sum, maximum) to this EXR");
  est->add_option("--max-uncertainty", a->request.input.max_uncertainty_deg,
                  "Largest 95 % cone (degrees) an answer may have; a method whose stated uncertainty is "
                  "wider declines and says so (default: no bound)");
  est->add_option("--plot", a->request.plot,
                  "Draw the answers over the middle frame's DoLP, AoLP and the pixels read, with the sun's track, "
                  "each pole's 95 % cone and the truth: a PNG with every method, or one PNG per method in a folder "
                  "(a path ending in / or an existing folder)");
  est->add_flag("--json", a->request.json, "Print the result as JSON");
  est->add_flag("--profile", a->request.profile,
                "On stderr, the wall and CPU seconds of reading the stack and of each method, and the peak "
                "resident memory after each (lines 'profile STAGE key=value ...')");
  est->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
  est->callback([a] {
    a->request.input.hemisphere = skypole::parse_hemisphere(a->hemisphere);
    a->request.input.use_site = skypole::parse_site_use(a->site);
    a->request.input.polarizer_model = skypole::parse_polarizer_model(a->polarizer_model);
    // Methods done, their rate and the time left, redrawn while one runs (terminal only).
    Ticker ticker(make_progress(a->quiet, "methods"));
    a->request.progress = [&ticker](std::size_t done, std::size_t total) { ticker(done, total); };
    a->request.before_output = [&ticker] { ticker.hide(); };
    skypole::print_estimate(a->request);
  });
}

}  // namespace skypol::cli
