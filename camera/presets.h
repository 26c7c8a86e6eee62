// Named lenses and sensors from the papers skypol reproduces, with where each number comes from.
// A number marked "nominal" is a typical value, not a measured one: calibrate your own camera.
#pragma once

#include <span>
#include <string_view>

#include "camera/dofp_sensor.h"
#include "camera/lens_factory.h"

namespace skypol::camera {

struct LensPreset {
  std::string_view name;   // the key a scene uses
  std::string_view model;  // a LensSpec model name
  double focal_mm;
  double fov_deg;          // full field of view
  std::string_view source;
};

struct SensorPreset {
  std::string_view name;
  int width, height;
  double pitch_um;
  DofpSensor dofp;  // width/height filled; noise figures as documented in source
  std::string_view source;
};

std::span<const LensPreset> lens_presets();
std::span<const SensorPreset> sensor_presets();

// Throw std::invalid_argument listing the legal names for an unknown one.
const LensPreset& lens_preset(std::string_view name);
const SensorPreset& sensor_preset(std::string_view name);

// The LensSpec of a preset lens on a preset sensor (principal point at the sensor centre).
LensSpec lens_spec(const LensPreset& lens, const SensorPreset& sensor);

}  // namespace skypol::camera
