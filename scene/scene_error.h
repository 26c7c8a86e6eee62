// Errors that point at the scene, pbrt-style: "file:line:col: error: key 'camera.fov_deg': …".
// Every user-facing problem with a scene or stack file is a SceneError, raised by the loader,
// never from deep inside the renderer.
#pragma once

#include <stdexcept>
#include <string>

namespace skypol::scene {

struct FileLoc {
  std::string file;
  int line = 0;    // 0 when unknown (then only the file is printed)
  int column = 0;
  std::string str() const;
};

class SceneError : public std::runtime_error {
 public:
  SceneError(const FileLoc& loc, const std::string& message);
  const FileLoc& where() const { return loc_; }

 private:
  FileLoc loc_;
};

}  // namespace skypol::scene
