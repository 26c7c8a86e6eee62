#include "render/scene_source.h"

#include <fstream>
#include <sstream>

#include "render/scene_error.h"

namespace skypol::render {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(FileLoc{path, 0, 0}, "cannot open scene file");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

}  // namespace

toml::table parse_toml(const std::string& text, const std::string& file_name) {
  try {
    return toml::parse(text, file_name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw SceneError(FileLoc{file_name, static_cast<int>(b.line), static_cast<int>(b.column)},
                     "TOML syntax: " + std::string(e.description()));
  }
}

SceneSource parse_scene_source(const std::string& text, const std::string& file_name) {
  return SceneSource{file_name, text, parse_toml(text, file_name)};
}

SceneSource load_scene_source(const std::string& path, const std::vector<Override>& overrides) {
  SceneSource source = parse_scene_source(read_text(path), path);
  if (!overrides.empty()) {
    throw SceneError(FileLoc{"--set", 0, 0}, "key '" + overrides.front().key + "': overrides are not supported yet");
  }
  return source;
}

}  // namespace skypol::render
