// Stokes stacks on disk: one multi-part OpenEXR file per time series, one part per frame, named by
// its ISO 8601 UTC time, every part's header carrying the truth (docs/exr-format.md lists the
// attributes). Written under a temporary name and renamed when complete: a failed or interrupted
// write leaves nothing behind.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "stack/frame.h"

namespace skypol::stack {

// What all parts of a stack share.
struct StackHeader {
  std::vector<std::string> bands{"Y"};
  std::string camera_description;  // TOML of the [camera] section (scene/scene.h)
  std::string scene_text;          // the scene as loaded (provenance)
  std::string sky_model;           // e.g. "rayleigh"
};

struct WriteOptions {
  bool half = false;
  std::string compression = "zip";  // none, zip, zips, piz, rle, pxr24, b44, b44a, dwaa, dwab
  int zip_level = 0;                // zip and zips: deflate level 1–9; 0: OpenEXR's default (4 in 3.1)
};

// Writes `truths.size()` parts; part i's pixels come from produce(i), called in order, so only
// one frame is in memory at a time. produce must return frames with exactly `channels`.
// Throws SceneError naming the path on any I/O problem; the temporary file is removed.
void write_stack(const std::string& path, const std::vector<scene::Truth>& truths, const std::vector<std::string>& channels,
                 int width, int height, const StackHeader& header, const WriteOptions& options,
                 const std::function<Frame(std::size_t)>& produce);

// The same, with produce(i) returning a frame that the caller owns and may refill for part i + 1
// (render::Renderer::render(sky, sun, frame)): a stack's pixel memory is then allocated once,
// not once per part, which on a virtual machine costs more than the rendering (`skypol bench`).
void write_stack_reusing(const std::string& path, const std::vector<scene::Truth>& truths,
                         const std::vector<std::string>& channels, int width, int height, const StackHeader& header,
                         const WriteOptions& options, const std::function<const Frame&(std::size_t)>& produce);

// OpenEXR's global thread pool as the writer and the reader set it (one thread per hardware
// thread); exposed so that a benchmark of OpenEXR alone runs with the same settings.
void use_all_cores_for_exr();

// Reads a stack back, all channels or only those named (a missing one is an error naming it).
// Rebuilds the camera from the header. Throws SceneError for a file that is not a skypol stack.
Stack read_stack(const std::string& path, const std::vector<std::string>& only_channels = {});

// The channel names and bands of a stack, from its first header (no pixels read).
struct StackSummary {
  int frames = 0;
  int width = 0, height = 0;
  std::vector<std::string> bands;
  std::vector<std::string> channels;
};
StackSummary peek_stack(const std::string& path);

// Header-only view: one line of truth per part and the stack's shared facts, for `skypol info`.
std::string describe_stack(const std::string& path);

}  // namespace skypol::stack
