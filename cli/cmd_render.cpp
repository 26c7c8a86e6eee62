// `skypol render SCENE` writes the stack; `skypol run SCENE` also estimates north on it.
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "cli/commands.h"
#include "skypole/report.h"
#include "render/pipeline.h"

namespace skypol::cli {
namespace {

struct RenderArgs {
  std::string scene;
  std::string out;
  bool out_given = false;  // -o was on the command line (perhaps as "")
  std::vector<std::string> set;  // --set key=value, in order
  bool quiet = false;
  std::string method = "classic";
  bool json = false;
};

// -o as given; "" is refused (it would silently fall back to output.path); a folder (an existing
// one, or a name ending in '/') receives <scene file's stem>.exr (README.md).
std::string output_path(const RenderArgs& a, const scene::Scene& scene) {
  if (!a.out_given) return scene.output.path;
  if (a.out.empty()) {
    throw std::invalid_argument("-o: the output path is empty (omit -o to write the scene's output.path, " +
                                scene.output.path + ")");
  }
  namespace fs = std::filesystem;
  std::error_code ec;
  if (a.out.back() == '/' || fs::is_directory(a.out, ec)) {
    return (fs::path(a.out) / (fs::path(a.scene).stem().string() + ".exr")).string();
  }
  return a.out;
}

std::string render_one(const RenderArgs& a) {
  std::vector<scene::Override> overrides;
  for (const std::string& s : a.set) overrides.push_back(scene::parse_override(s));
  const scene::Scene scene = scene::load_scene(a.scene, overrides);
  if (!a.quiet)
    for (const std::string& n : scene.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
  const std::string out = output_path(a, scene);
  const render::RenderReport r = render::render_scene(scene, out, make_progress(a.quiet));
  if (!a.quiet) {
    std::fprintf(stderr, "wrote %s: %zu frame(s) %dx%d (rays %.2f s, sky %.2f s, encode+write %.2f s)\n", out.c_str(),
                 r.frames, r.width, r.height, r.setup_seconds, r.render_seconds, r.write_seconds);
  }
  return out;
}

}  // namespace

void add_render(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* render = app.add_subcommand("render", "Render a scene into a multi-part EXR Stokes stack");
  render->add_option("scene", args->scene, "Scene file (TOML, docs/scenes.md)")->required();
  CLI::Option* render_out = render->add_option(
      "-o,--output", args->out, "Output EXR, or a folder for <scene name>.exr (default: the scene's output.path)");
  render->add_option("--set", args->set, "Override a scene key: --set camera.heading_deg=30 (repeatable)")
      ->allow_extra_args(false);
  render->add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
  render->callback([args, render_out] {
    args->out_given = render_out->count() > 0;
    render_one(*args);
  });

  auto run_args = std::make_shared<RenderArgs>();
  CLI::App* run = app.add_subcommand("run", "Render a scene, then estimate north on the stack and score it");
  run->add_option("scene", run_args->scene, "Scene file (TOML, docs/scenes.md)")->required();
  CLI::Option* run_out = run->add_option(
      "-o,--output", run_args->out, "Output EXR, or a folder for <scene name>.exr (default: the scene's output.path)");
  run->add_option("--set", run_args->set, "Override a scene key: --set camera.heading_deg=30 (repeatable)")
      ->allow_extra_args(false);
  run->add_option("-m,--method", run_args->method, "Estimator (see `skypol estimate --help`)");
  run->add_flag("--json", run_args->json, "Print the result as JSON");
  run->add_flag("-q,--quiet", run_args->quiet, "No progress or summary on stderr");
  run->callback([run_args, run_out] {
    run_args->out_given = run_out->count() > 0;
    const std::string out = render_one(*run_args);
    skypole::print_estimate(out, run_args->method, run_args->json);
  });
}

}  // namespace skypol::cli
