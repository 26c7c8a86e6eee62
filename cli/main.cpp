// skypol: render skylight polarization stacks and find north in them. See README.md.
#include <cstdio>
#include <exception>

#include "cli/commands.h"
#include "scene/scene_error.h"

int main(int argc, char** argv) {
  CLI::App app{"skypol: a physically based renderer of skylight polarization and a benchmark for "
               "the estimators that find north in it"};
  app.require_subcommand(1);
  app.set_version_flag("--version", skypol::cli::version_text());
  skypol::cli::add_render(app);
  skypol::cli::add_estimate(app);
  skypol::cli::add_evaluate(app);
  skypol::cli::add_methods(app);
  skypol::cli::add_info(app);
  skypol::cli::add_sun(app);
  skypol::cli::add_lens(app);
  skypol::cli::add_bench(app);
  skypol::cli::add_sweep(app);
  skypol::cli::add_bench_occluders(app);
  skypol::cli::add_preview(app);
  skypol::cli::add_reproduce(app);
  skypol::cli::add_tradeoff(app);
  skypol::cli::add_table(app);
  skypol::cli::add_import(app);
  skypol::cli::add_export(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const skypol::scene::SceneError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
