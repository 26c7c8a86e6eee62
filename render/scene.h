// A scene: everything one stack is rendered from, read from a TOML file (docs/scenes.md lists
// every key with its unit, default and range). The loader checks every value and reports problems
// as SceneError with file, line, column and key; the renderer only ever sees checked values.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "render/toml_fields.h"
#include "sky/sky_model.h"
#include "sky/sun.h"
#include "sky/time.h"

namespace skypol::render {

struct CameraSpec {
  std::string model = "equidistant";   // a camera::Mapping name
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels (from focal_mm / pitch_um when not given)
  double fov_deg = 180;                // full field of view imaged (2·θmax)
  double heading_deg = 0, tilt_deg = 0, roll_deg = 0;
  camera::Transport transport = camera::Transport::meridional;
  std::string description;             // canonical TOML of this section, stored in the EXR headers
};

struct SkySpec {
  std::string model = "rayleigh";
  double max_dolp = 1.0;
};

struct RenderSpec {
  int spp = 1;
  std::uint64_t seed = 0;
  std::vector<std::string> bands{"Y"};
};

struct OutputSpec {
  std::string path;                    // resolved against the current directory
  std::vector<std::string> channels{"S0", "S1", "S2", "DoLP", "AoLP", "mask"};
  bool half = false;                   // pixel type: float32 (default) or half
  std::string compression = "zip";
};

struct Scene {
  std::string file;                    // as given (for messages)
  std::string text;                    // the scene as loaded, for provenance in the headers
  sky::Site site;
  sky::SunOptions sun_options;
  std::vector<sky::Instant> times;
  CameraSpec camera;
  SkySpec sky;
  RenderSpec render;
  OutputSpec output;
};

// Throws SceneError (missing file, TOML syntax, wrong type, unknown key, value out of range).
Scene load_scene(const std::string& path);
Scene parse_scene(const std::string& text, const std::string& file_name);

// The camera section alone (also how a stack's header is turned back into a camera).
CameraSpec read_camera(Fields& camera_table);
CameraSpec parse_camera(const std::string& toml_text, const std::string& file_name);

// Built from checked specs; throws SceneError only for combinations a single key cannot catch.
std::shared_ptr<const camera::Camera> build_camera(const CameraSpec& spec);
std::unique_ptr<sky::SkyModel> build_sky(const SkySpec& spec);

}  // namespace skypol::render
