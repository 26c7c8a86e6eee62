#include "scene/scene_error.h"

namespace skypol::scene {

std::string FileLoc::str() const {
  if (line <= 0) return file;
  return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

SceneError::SceneError(const FileLoc& loc, const std::string& message)
    : std::runtime_error(loc.str() + ": error: " + message), loc_(loc) {}

}  // namespace skypol::scene
