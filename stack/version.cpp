// SKYPOL_VERSION and SKYPOL_GIT_DESCRIBE come from stack/CMakeLists.txt, for this file only.
#include "stack/version.h"

namespace skypol::stack {

std::string version_text() {
  std::string v = "skypol " SKYPOL_VERSION;
  const std::string git = SKYPOL_GIT_DESCRIBE;
  if (!git.empty()) v += " (git " + git + ")";
  return v;
}

}  // namespace skypol::stack
