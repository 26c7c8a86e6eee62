// `skypol methods [--json]`: the estimators of the registry (skypole/method_registry.h), with what
// each does and its traits; --json gives scripts the list and the committed calibrations.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "skypole/method_registry.h"

namespace skypol::cli {

void add_methods(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand("methods", "List the estimators: what each does, its traits and calibration");
  cmd->add_flag("--json", *json, "Print the registry as JSON (name, description, traits, calibration)");
  cmd->callback([json] {
    if (*json) {
      std::fputs(skypole::methods_json().c_str(), stdout);
      return;
    }
    for (const skypole::Method& m : skypole::methods()) {
      const skypole::MethodTraits& t = m.traits;
      std::printf("%-22s %s\n%-22s frame jackknife ≤ %d groups%s%s%s\n", m.name.c_str(), m.description.c_str(), "",
                  t.frame_jackknife_max_groups, t.sector_jackknife ? ", sector jackknife" : "",
                  t.needs_site ? ", needs the site" : "", t.used_by_auto ? "" : ", not used by auto");
    }
    std::printf("%-22s %s\n", "auto",
                "the answer most methods agree with (skypole/evaluate.h); site-free without the site");
  });
}

}  // namespace skypol::cli
