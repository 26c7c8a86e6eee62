// `skypol info STACK.exr`: the frames of a stack and their truth, for a person to read, or with
// --json every header attribute of every part at full precision, for a program.
#include <cstdio>

#include "cli/commands.h"
#include "stack/stack_io.h"

namespace skypol::cli {

void add_info(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* info = app.add_subcommand("info", "Print a stack's frames and the truth in their headers");
  info->add_option("stack", *path, "A stack written by skypol render or skypol import")->required();
  info->add_flag("--json", *json, "Every header attribute of every part as JSON (numbers at %.17g)");
  info->callback([path, json] {
    std::fputs((*json ? stack::describe_stack_json(*path) : stack::describe_stack(*path)).c_str(), stdout);
  });
}

}  // namespace skypol::cli
