// A scene from file to stack on disk: truth for every time, the renderer, the EXR writer. What
// `skypol render` and `skypol run` do, callable from tests and benchmarks.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "scene/scene.h"

namespace skypol::render {

struct RenderReport {
  std::string path;
  std::size_t frames = 0;
  int width = 0, height = 0;  // of each frame (after binning)
  double setup_seconds = 0;   // camera rays (and occlusion) and frame memory, once per stack
  double render_seconds = 0;  // sky evaluation, all frames
  double write_seconds = 0;   // encoding and writing, all frames
  int tables_built = 0;       // VRTE tables solved (vrte sky only; 0 with warm tables)
  int tables_read = 0;        // VRTE tables read from the cache (sky/sky_spec.h: default_table_cache_dir)
};

// progress(done, total) is called after each frame (may be empty). table_cache_dir: where a vrte
// sky's tables are read and written (nullopt: sky::default_table_cache_dir(); empty: no cache).
RenderReport render_scene(const scene::Scene& scene, const std::string& out_path,
                          const std::function<void(std::size_t, std::size_t)>& progress = {},
                          const std::optional<std::filesystem::path>& table_cache_dir = std::nullopt);

}  // namespace skypol::render
