// `skypol preview STACK.exr [-o DIR]`: PNG previews of every frame of a stack (stack/preview.h).
#include <cstdio>

#include "cli/commands.h"
#include "stack/preview.h"

namespace skypol::cli {

void add_preview(CLI::App& app) {
  struct Args {
    std::string stack;
    std::string out;
  };
  auto a = std::make_shared<Args>();
  CLI::App* preview = app.add_subcommand("preview", "Write PNG previews (S0, DoLP, AoLP, colour bars) of a stack's frames");
  preview->add_option("stack", a->stack, "Stack file (EXR written by skypol render)")->required();
  preview->add_option("-o,--output", a->out, "Folder for the PNGs (default: next to the stack, <name>-preview)");
  preview->callback([a] {
    const std::string folder = a->out.empty() ? stack::preview_folder_for(a->stack) : a->out;
    const std::size_t n = stack::write_stack_previews(a->stack, folder);
    std::printf("wrote %zu preview(s) into %s\n", n, folder.c_str());
  });
}

}  // namespace skypol::cli
