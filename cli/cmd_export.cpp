// `skypol export STACK -f npy|exr|tiff|png`: a stack's frames as single-part files for OpenCV,
// NumPy and ImageMagick (stack/export.h; docs/exr-format.md).
#include <cstdio>

#include "cli/commands.h"
#include "stack/export.h"

namespace skypol::cli {

void add_export(CLI::App& app) {
  struct Args {
    std::string stack;
    stack::ExportOptions options;
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("export", "Write a stack's frames as single-part EXR, TIFF, NPY or PNG files, "
                                               "one per frame, with a times.csv");
  cmd->add_option("stack", a->stack, "A stack (skypol render or import)")->required();
  cmd->add_option("-f,--format", a->options.format, "exr, tiff, npy (default) or png");
  cmd->add_option("-c,--channels", a->options.channels,
                  "Channels, comma-separated: S0,S1,S2,S3,DoLP,AoLP (of --band), raw, mask, or full names "
                  "(default S0,S1,S2,DoLP,AoLP)")
      ->delimiter(',');
  cmd->add_option("--band", a->options.band, "Band of S0..AoLP (default: the stack's first)");
  cmd->add_option("-o,--output", a->options.out_dir, "Folder for the files (created; default .)");
  cmd->add_flag("-q,--quiet", a->quiet, "No summary on stderr");
  cmd->callback([a] {
    const std::vector<std::string> files = stack::export_stack(a->stack, a->options);
    if (!a->quiet) {
      std::fprintf(stderr, "wrote %zu file(s) and times.csv in %s\n", files.size(), a->options.out_dir.c_str());
    }
  });
}

}  // namespace skypol::cli
