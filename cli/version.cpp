// `skypol --version`: the same text every stack's skypol:version header carries (stack/version.h).
#include "cli/commands.h"
#include "stack/version.h"

namespace skypol::cli {

std::string version_text() { return stack::version_text(); }

}  // namespace skypol::cli
