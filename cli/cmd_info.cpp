// `skypol info STACK.exr`: the frames of a stack and their truth, for a person to read.
#include <cstdio>

#include "cli/commands.h"
#include "stack/stack_io.h"

namespace skypol::cli {

void add_info(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* info = app.add_subcommand("info", "Print a stack's frames and the truth in their headers");
  info->add_option("stack", *path, "A stack written by skypol render")->required();
  info->callback([path] { std::fputs(stack::describe_stack(*path).c_str(), stdout); });
}

}  // namespace skypol::cli
