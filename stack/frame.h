// What the renderer produces and what the estimators consume: frames of named float channels with
// the ground truth the renderer knows, and a stack of them sharing one camera.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "camera/camera.h"
#include "scene/truth.h"

namespace skypol::stack {

// What a frame's AoLP assumes of the sensor's micro-polarizers (skypol:polarizerAngles,
// docs/exr-format.md). `none`: ideal Stokes, no sensor. `calibrated`: the angles the polarizers
// have (a demosaic that inverts the sensor's own analyzer, or polarizers at the nominal angles the
// demosaic assumes). `nominal`: the nominal angles, whatever the polarizers' own (an uncalibrated
// pipeline: its AoLP may carry their error, which the AoLP sun fits then model, sun_vector.h).
enum class PolarizerAngles : std::uint8_t { none, calibrated, nominal };
// "none", "calibrated", "nominal"; and back (nullopt for any other name).
const char* polarizer_angles_name(PolarizerAngles a);
std::optional<PolarizerAngles> polarizer_angles_named(std::string_view name);

// A frame: width×height pixels, row-major (index = y·width + x), one float vector per channel.
// Channel names follow docs/exr-format.md: "S0.<band>" … "S3.<band>", "DoLP.<band>", "AoLP.<band>" (radians
// in memory, as in the file), "mask" (1 = sky seen, 0 = outside the image circle or occluded),
// and for RGB bands also "R", "G", "B".
struct Frame {
  int width = 0;
  int height = 0;
  scene::Truth truth;  // scene/truth.h
  std::map<std::string, std::vector<float>> channels;
  // The exposure (µs) the sensor took this frame with, fixed or metered (skypol:exposureUs,
  // docs/exr-format.md); none for ideal Stokes (no [sensor]).
  std::optional<double> exposure_us;
  PolarizerAngles polarizer_angles = PolarizerAngles::none;
  // Which renderer left every channel zero outside its spans of the image circle (a token of
  // render::Renderer, 0 for none), so that its next render into this frame, when the caller lets
  // it (RenderOptions::reuse_cleared), need not clear those pixels again. Whatever else writes
  // the channels resets it to 0.
  std::uint64_t zero_outside = 0;

  bool has(const std::string& name) const { return channels.count(name) != 0; }
  // Throws std::out_of_range naming the channel and the ones that exist.
  const std::vector<float>& channel(const std::string& name) const;
  std::vector<float>& channel(const std::string& name);
};

// Makes `channel` hold n floats, keeping its storage when it already does (the renderer reuses a
// frame's channels from one frame to the next). New storage is asked of the OS in huge pages where
// it can (Linux transparent huge pages): on a virtual machine a first-touch fault per 4 KiB page
// costs more than rendering that page (`skypol bench`: "frame memory" against "sky render").
// New values are zero.
void size_channel(std::vector<float>& channel, std::size_t n);

// A time series seen by one camera (one EXR file, one part per frame).
struct Stack {
  std::shared_ptr<const camera::Camera> camera;
  std::vector<std::string> bands;     // e.g. {"Y"} or {"R","G","B"}
  std::vector<Frame> frames;          // in time order
  std::string camera_description;     // the camera's scene text, enough to rebuild `camera`
  std::string scene_text;             // provenance: the whole scene as loaded
  // false for an imported capture (skypol import): its times, camera and attitude are the user's,
  // but its heading and pole are what the estimators are asked for, so there is nothing to score
  // against (frames' truth then holds heading 0 and no pole pixel; docs/exr-format.md).
  bool truth_known = true;
  // false when the capture's site was not given: frames' site and sun are then zeros, unusable.
  bool site_known = true;
};

}  // namespace skypol::stack
