// `skypol import CAPTURE.toml -o STACK.exr`: a real camera's raw frames into a stack whose truth
// is marked unknown (stack/capture_import.h; docs/import.md).
#include <cstdio>

#include "cli/commands.h"
#include "stack/capture_import.h"

namespace skypol::cli {

void add_import(CLI::App& app) {
  struct Args {
    std::string capture, out;
    std::vector<std::string> set;
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("import", "Read a camera's raw polarization frames (PNG, TIFF, NPY) into a "
                                               "stack, its truth marked unknown, for skypol estimate");
  cmd->add_option("capture", a->capture, "Capture file (TOML: [capture], [camera], [sensor], optional [site]; "
                                         "docs/import.md)")->required();
  cmd->add_option("-o,--output", a->out, "Output stack (EXR)")->required();
  cmd->add_option("--set", a->set, "Override a key of the capture file: --set site.latitude_deg=43.3 (repeatable)")
      ->allow_extra_args(false);
  cmd->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd->callback([a] {
    if (a->out.empty()) throw std::invalid_argument("-o: the output path is empty");
    std::vector<scene::Override> overrides;
    for (const std::string& s : a->set) overrides.push_back(scene::parse_override(s));
    const stack::ImportReport r = stack::import_capture(a->capture, a->out, overrides, make_progress(a->quiet));
    if (!a->quiet) {
      std::string bands;
      for (const std::string& b : r.bands) bands += (bands.empty() ? "" : ",") + b;
      std::fprintf(stderr, "wrote %s: %zu frame(s) %dx%d, bands %s, truth unknown%s\n", a->out.c_str(), r.frames,
                   r.width, r.height, bands.c_str(), r.site_known ? "" : ", site unknown");
    }
  });
}

}  // namespace skypol::cli
