// The version skypol reports, from one source: `skypol --version` prints it and every stack's
// header carries it as skypol:version (docs/exr-format.md).
#pragma once

#include <string>

namespace skypol::stack {

// "skypol 0.1.0", and " (git DESCRIBE)" in a git checkout: the project's version (CMakeLists.txt)
// and `git describe --tags --always --dirty` as it was when CMake last configured the build (a
// commit after that shows only after the next configure).
std::string version_text();

}  // namespace skypol::stack
