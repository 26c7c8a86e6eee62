// `skypol estimate STACK`: north from a stack, scored against the truth in its headers.
#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/estimate_report.h"
#include "render/stack_io.h"
#include "skypole/classic.h"

namespace skypol::cli {
namespace {

const std::vector<std::string> kMethods{"classic"};

skypole::PoleEstimate run_method(const render::Stack& stack, const std::string& method) {
  if (method == "classic") return skypole::estimate_classic(stack).estimate;
  std::string legal;
  for (const std::string& m : kMethods) legal += (legal.empty() ? "" : ", ") + m;
  throw std::invalid_argument("unknown method '" + method + "' (expected one of " + legal + ")");
}

// Only the channels the estimators read: DoLP and AoLP of every band, and the mask.
std::vector<std::string> estimator_channels(const std::string& path) {
  const render::StackSummary s = render::peek_stack(path);
  std::vector<std::string> want;
  for (const std::string& c : s.channels) {
    if (c == "mask" || c.rfind("DoLP.", 0) == 0 || c.rfind("AoLP.", 0) == 0) want.push_back(c);
  }
  return want;
}

// A number with `decimals` decimals (and a sign if `sign`), or "null" where it is undefined.
std::string number_or_null(const std::optional<double>& v, int decimals, bool sign = false) {
  if (!v) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, sign ? "%+.*f" : "%.*f", decimals, *v);
  return buf;
}

}  // namespace

void print_estimate(const std::string& path, const std::string& method, bool json) {
  if (std::find(kMethods.begin(), kMethods.end(), method) == kMethods.end()) run_method({}, method);  // throws
  const render::Stack stack = render::read_stack(path, estimator_channels(path));
  const skypole::PoleEstimate e = run_method(stack, method);
  const render::Truth& t = stack.frames.at(0).truth;
  const double true_lat = t.site.latitude_deg;
  if (!e.valid) throw std::invalid_argument(path + ": " + method + " found no pole: " + e.why_invalid);
  const skypole::Score s = skypole::score(e, t);
  if (json) {
    std::printf("{\"stack\": \"%s\", \"method\": \"%s\", \"frames\": %zu, \"seconds\": %.4f,\n", path.c_str(),
                method.c_str(), stack.frames.size(), e.seconds);
    std::printf(" \"latitude_deg\": %.6f, \"true_latitude_deg\": %.6f, \"latitude_error_deg\": %.6f,\n", e.latitude_deg,
                true_lat, s.latitude_error_deg);
    std::printf(" \"heading_deg\": %s, \"true_heading_deg\": %.6f, \"bearing_error_deg\": %s,\n",
                number_or_null(e.heading_deg, 6).c_str(), t.heading_deg,
                number_or_null(s.bearing_error_deg, 6).c_str());
    std::printf(" \"angular_error_deg\": %.6f, \"pole\": \"%s\", \"residual_deg\": %.6f, \"confidence\": %.4f}\n",
                s.angular_error_deg, e.is_north ? "north" : "south", e.residual_deg, e.confidence);
    return;
  }
  std::printf("stack    %s (%zu frames, %dx%d)\n", path.c_str(), stack.frames.size(), stack.frames[0].width,
              stack.frames[0].height);
  std::printf("method   %s (%.3f s)%s%s\n", method.c_str(), e.seconds, e.note.empty() ? "" : "; ", e.note.c_str());
  std::printf("%-24s %12s %12s %12s\n", "", "estimate", "truth", "error");
  std::printf("%-24s %12.3f %12.3f %+12.3f\n", "latitude (deg)", e.latitude_deg, true_lat, s.latitude_error_deg);
  std::printf("%-24s %12s %12.3f %12s\n", "north bearing (deg)", number_or_null(e.heading_deg, 3).c_str(),
              t.heading_deg, number_or_null(s.bearing_error_deg, 3, true).c_str());
  std::printf("%-24s %12s %12s %12.3f\n", "pole on the sphere (deg)", e.is_north ? "north" : "south",
              t.pole_is_north ? "north" : "south", s.angular_error_deg);
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
  est->add_option("-m,--method", a->method, "Estimator: classic (the SkyPole paper's)");
  est->add_flag("--json", a->json, "Print the result as JSON");
  est->callback([a] { print_estimate(a->stack, a->method, a->json); });
}

}  // namespace skypol::cli
