// A method by its name, alone (run_bare.h).
#include "skypole/run_bare.h"

#include <stdexcept>
#include <string>

#include "stack/frame.h"

namespace skypol::skypole {

void check_site(const Method& method, const stack::Stack& stack, const InputOptions& input) {
  if (!method.traits.needs_site || site_usable(stack, input)) return;
  if (!stack.site_known) {
    // An imported capture without [site]: the ephemeris has nothing to be computed for.
    throw std::invalid_argument(method.name + " needs the site, and this capture's is unknown "
                                              "(give [site] when importing)");
  }
  throw std::invalid_argument(method.name + " needs the site, and it was withheld (--site unknown): "
                                            "the stack's site and times are not used");
}

PoleEstimate run_bare(const SkyView& view, const Method& method) {
  check_site(method, view.stack(), view.input());
  return method.bare(view);
}

PoleEstimate run_bare(const SkyView& view, std::string_view method) { return run_bare(view, method_entry(method)); }

}  // namespace skypol::skypole
