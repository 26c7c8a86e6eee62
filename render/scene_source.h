// Where a scene's TOML comes from before its keys are read: the file, the files it includes, and
// the command line's --set overrides, merged into one table whose nodes still carry the file and
// line they came from (so that errors point at the right place).
#pragma once

#include <string>
#include <vector>

#include <toml++/toml.h>

namespace skypol::render {

// One `--set dotted.key=value` override; `value` is TOML ("3", "\"piz\"", "[1, 2]"), or a bare
// word taken as a string.
struct Override {
  std::string key;
  std::string value;
};

struct SceneSource {
  std::string file;   // the scene file as given
  std::string text;   // the merged scene as TOML text (provenance for the stack's headers)
  toml::table root;
};

// Throws SceneError: file missing, TOML syntax, bad override.
SceneSource load_scene_source(const std::string& path, const std::vector<Override>& overrides = {});
SceneSource parse_scene_source(const std::string& text, const std::string& file_name);

// TOML text → table, with syntax errors as SceneError at the file, line and column.
toml::table parse_toml(const std::string& text, const std::string& file_name);

}  // namespace skypol::render
