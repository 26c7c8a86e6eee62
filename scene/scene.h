// A scene: everything one stack is rendered from, read from a TOML file (docs/scenes.md lists
// every key with its unit, default and range). The loader checks every value and reports problems
// as SceneError with file, line, column and key; the renderer only ever sees checked values.
//
// Each section has its own reader, in its own file: scene.cpp (site, atmosphere, time, render,
// output), scene_camera.cpp, scene_sky.cpp, scene_sensor.cpp, scene_occluders.cpp; where the
// TOML comes from (includes, --set) is scene_source.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/calibration_import.h"
#include "camera/camera.h"
#include "camera/dofp_sensor.h"
#include "camera/lens_factory.h"
#include "scene/occluder_spec.h"
#include "scene/output_defaults.h"
#include "scene/scene_source.h"
#include "scene/toml_fields.h"
#include "sky/sky_model.h"
#include "sky/sky_spec.h"
#include "sky/sun.h"
#include "sky/time.h"

namespace skypol::scene {

struct CameraSpec {
  camera::LensSpec lens;               // checked by camera::make_lens
  // The calibration file the lens came from (calibration = ... or an OCamCalib path), text
  // included, so that a stack's header rebuilds the lens without the file.
  std::optional<camera::Calibration> calibration;
  // Orientation (camera/orientation.h). A quaternion in the scene is turned into these angles, so
  // the truth and the headers always carry heading, tilt and roll.
  double heading_deg = 0, tilt_deg = 0, roll_deg = 0;
  camera::Transport transport = camera::Transport::meridional;
  std::string description;             // canonical TOML of this section, stored in the EXR headers
};

// The [sensor] section: a division-of-focal-plane polarization sensor between the sky and the
// file. Absent: the stack holds the ideal Stokes vectors.
struct SensorSpec {
  camera::DofpSensor dofp;
  camera::Demosaic demosaic = camera::Demosaic::nominal;
  // exposure = "auto": each frame's exposure_us is metered (camera/dofp_sensor.h, AutoExposure)
  // instead of dofp.exposure_us, the fixed exposure of every frame otherwise.
  std::optional<camera::AutoExposure> auto_exposure;
};

struct RenderSpec {
  int spp = 1;
  std::uint64_t seed = 0;
  std::vector<std::string> bands{"Y"};
};

struct OutputSpec {
  std::string path;                    // resolved against the current directory
  std::vector<std::string> channels{"S0", "S1", "S2", "DoLP", "AoLP", "mask"};
  bool half = kDefaultHalf;            // pixel type (output_defaults.h)
  std::string compression = "zip";     // docs/scenes.md lists them and marks the lossy ones
  int zip_level = 0;                   // zip, zips: deflate level 1–9; 0: OpenEXR's default
  bool allow_lossy = false;            // opt-in for a compression that changes Stokes values
  bool previews = false;               // PNG previews next to the stack (stack/preview.h)
};

struct Scene {
  std::string file;                    // as given (for messages)
  std::string text;                    // the scene as loaded, for provenance in the headers
  sky::Site site;
  sky::SunOptions sun_options;
  std::vector<sky::Instant> times;
  CameraSpec camera;
  sky::SkySpec sky;
  std::optional<SensorSpec> sensor;
  OccluderSpec occluders;
  RenderSpec render;
  OutputSpec output;
  std::vector<std::string> notes;      // SceneSource::notes: what loading dropped (for stderr)
};

// Throws SceneError (missing file, TOML syntax, wrong type, unknown key, value out of range).
Scene load_scene(const std::string& path, const std::vector<Override>& overrides = {});
Scene parse_scene(const std::string& text, const std::string& file_name);
Scene scene_from_source(const SceneSource& source);

// The camera section alone (also how a stack's header is turned back into a camera). Relative
// file names in it (ocamcalib_path) resolve against the folder of Fields::file().
CameraSpec read_camera(Fields& camera_table);
CameraSpec parse_camera(const std::string& toml_text, const std::string& file_name);
// The [site] section: latitude_deg, longitude_deg (required), height_m. The scene and a capture's
// import file read it here, so both check the same ranges and name the same keys.
sky::Site read_site(Fields& site_table);
sky::SkySpec read_sky(Fields& sky_table);
// What the sky's model asks of the rest of the scene (its bands, its site: sky::validate_for_scene),
// as a SceneError at the [sky] key the check names.
void check_sky_for_scene(const Fields& sky_table, const Scene& scene);
SensorSpec read_sensor(Fields& sensor_table, const CameraSpec& camera);
OccluderSpec read_occluders(Fields& occluders_table);
// The [output] section (scene_output.cpp); `stem` names the default path out/<stem>.exr. A lossy
// compression without allow_lossy is an error at the compression key naming what it loses.
OutputSpec read_output(Fields& output_table, const std::string& stem, bool has_sensor);
// What `compression` on `half` or float Stokes channels loses, as measured by `skypol tradeoff
// compression` (docs/benchmarks.md); empty when it is lossless.
std::string lossy_compression_loss(const std::string& compression, bool half);

// Built from checked specs; throws SceneError only for combinations a single key cannot catch.
std::shared_ptr<const camera::Camera> build_camera(const CameraSpec& spec);
std::unique_ptr<sky::SkyModel> build_sky(const sky::SkySpec& spec);

// The site's air for the Rayleigh optical depth: [atmosphere] pressure_hpa, or 1013.25 hPa when it
// is 0 or absent (refraction off: the depth still needs a pressure); the site's height and latitude.
sky::SiteAtmosphere site_atmosphere(const Scene& scene);
// The scene's sky per band: one model for every band (grey models, exactly build_sky), or one per
// band (vrte), its tables read from or written to cache_dir (empty: solved, not cached).
sky::BandSkies build_band_skies(const Scene& scene, const std::filesystem::path& cache_dir);

}  // namespace skypol::scene
