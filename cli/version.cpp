// `skypol --version`. SKYPOL_VERSION and SKYPOL_GIT_DESCRIBE come from cli/CMakeLists.txt: the
// project's version, and `git describe` as it was when CMake last configured the build (a
// commit after that shows only after the next configure; the stacks' skypol:version is separate).
#include "cli/commands.h"

namespace skypol::cli {

std::string version_text() {
  std::string v = "skypol " SKYPOL_VERSION;
  const std::string git = SKYPOL_GIT_DESCRIBE;
  if (!git.empty()) v += " (git " + git + ")";
  return v;
}

}  // namespace skypol::cli
