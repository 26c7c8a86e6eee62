// `skypol estimate STACK`: north from a stack, scored against the truth in its headers.
#include <stdexcept>

#include "cli/commands.h"
#include "cli/estimate_report.h"

namespace skypol::cli {

void print_estimate(const std::string& path, const std::string& method, bool json) {
  (void)path;
  (void)json;
  throw std::invalid_argument("estimator '" + method + "' is not available yet");
}

void add_estimate(CLI::App& app) {
  struct Args {
    std::string stack;
    std::string method = "classic";
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* est = app.add_subcommand("estimate", "Estimate north and latitude on a stack; score against its truth");
  est->add_option("stack", a->stack, "A stack written by skypol render")->required();
  est->add_option("-m,--method", a->method, "Estimator");
  est->add_flag("--json", a->json, "Print the result as JSON");
  est->callback([a] { print_estimate(a->stack, a->method, a->json); });
}

}  // namespace skypol::cli
