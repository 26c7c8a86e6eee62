#include <cstdio>
#include <unistd.h>

#include "cli/commands.h"

namespace skypol::cli {

Progress make_progress(bool quiet) { return Progress{!quiet && ::isatty(STDERR_FILENO) != 0}; }

void Progress::operator()(std::size_t done, std::size_t total) const {
  if (!enabled || total == 0) return;
  constexpr int width = 40;
  const int filled = static_cast<int>(width * done / total);
  std::fprintf(stderr, "\r[%.*s%*s] %zu/%zu frames", filled, "########################################", width - filled, "",
               done, total);
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

}  // namespace skypol::cli
