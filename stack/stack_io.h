// Stokes stacks on disk: one multi-part OpenEXR file per time series, one part per frame, named by
// its ISO 8601 UTC time, every part's header carrying the truth (docs/exr-format.md lists the
// attributes). Written under a temporary name and renamed when complete: a failed or interrupted
// write leaves nothing behind.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "scene/output_defaults.h"
#include "stack/frame.h"

namespace skypol::stack {

// What all parts of a stack share.
struct StackHeader {
  std::vector<std::string> bands{"Y"};
  std::string camera_description;  // TOML of the [camera] section (scene/scene.h)
  std::string scene_text;          // the scene as loaded (provenance)
  std::string sky_model;           // e.g. "rayleigh"
  // An imported capture (stack/capture_import.h) says what it does not know: without the truth
  // the heading, world-from-camera, pole and pole pixel attributes are left out and
  // skypol:truth = "unknown"; without the site also the site's and the sun's
  // (skypol:siteKnown = 0). docs/exr-format.md, "Captures".
  bool truth_known = true;
  bool site_known = true;
  // Further string attributes a writer adds (names "skypol:…" that the format does not already
  // use): `attributes` on every part, part_attributes[i] on part i (when there are that many), e.g.
  // an imported database's source of truth and each frame's weather label (docs/import.md).
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<std::vector<std::pair<std::string, std::string>>> part_attributes;
  // Frames through a sensor: every part carries skypol:exposureUs, the Frame::exposure_us of the
  // frame written into it (which must have one). Parts' headers precede every pixel in the file,
  // and a metered exposure is known only once its frame is rendered, so the writer reserves the
  // attribute and fills in each part's value when the file is complete.
  bool exposures = false;
  // Frames through a sensor: what their AoLP assumes of its polarizers, on every part as
  // skypol:polarizerAngles (stack/frame.h, PolarizerAngles); none writes no attribute.
  PolarizerAngles polarizer_angles = PolarizerAngles::none;
};

// Defaults: the renders' (scene/output_defaults.h), so every writer of stacks agrees by default.
struct WriteOptions {
  bool half = scene::kDefaultHalf;
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

// The same with the next part rendered while this one is encoded and written: fill(i, frame)
// writes part i's pixels into `frame`, one of `frames` taken in turn (each reused every other
// part; their storage stays with the caller for its next stack). fill is called in order
// i = 0, 1, …, never twice at once, from a second thread for i > 0; it runs alongside OpenEXR's
// encoding of part i − 1, so the render and the compressor share the cores. Returns the seconds
// spent encoding and writing parts (on the calling thread; the rendering overlaps them).
double write_stack_overlapped(const std::string& path, const std::vector<scene::Truth>& truths,
                            const std::vector<std::string>& channels, int width, int height, const StackHeader& header,
                            const WriteOptions& options, std::array<Frame, 2>& frames,
                            const std::function<void(std::size_t, Frame&)>& fill);

// The same, part by part and each part in bands of band_rows rows (the last band of a part may be
// shorter): fill(i, y0, y1, band) writes rows [y0, y1) of part i into `band` (a frame of
// width × (y1 − y0) pixels; render::Renderer::render_rows), one of `bands` taken in turn. The next
// band is filled on a second thread while this one is encoded and written, as
// write_stack_overlapped does for whole parts, but the memory is two bands, not two frames: it is
// faulted in once and stays in cache for OpenEXR's copy. Same file, byte for byte. fill is called
// in order, never twice at once. Returns the seconds spent encoding and writing.
double write_stack_banded(const std::string& path, const std::vector<scene::Truth>& truths,
                          const std::vector<std::string>& channels, int width, int height, const StackHeader& header,
                          const WriteOptions& options, int band_rows, std::array<Frame, 2>& bands,
                          const std::function<void(std::size_t, int, int, Frame&)>& fill);

// Whether a stack with these options is encoded on the calling thread alone (uncompressed: its
// encoding is a copy, and OpenEXR's pool is left out, stack_io.cpp). The other core is then free
// to render the next part meanwhile (write_stack_overlapped); a compressed stack's encoding
// already uses every core.
bool encodes_on_calling_thread(const WriteOptions& options);

// OpenEXR's global thread pool as the writer and the reader set it (one thread per hardware
// thread; an uncompressed stack is written without it, see stack_io.cpp); exposed so that a
// benchmark of OpenEXR alone runs with the same settings.
void use_all_cores_for_exr();

// Reads a stack back, all channels or only those named (a missing one is an error naming it).
// Rebuilds the camera from the header. Throws SceneError for a file that is not a skypol stack.
Stack read_stack(const std::string& path, const std::vector<std::string>& only_channels = {});
// The same, one frame at a time: each(i, frame) is called with part i's frame as soon as it is
// read, in order, so that only one frame is in memory (skypol export). Returns the stack's shared
// facts (camera, bands, scene, what is known) without frames. What `each` throws is passed on.
Stack read_stack_frames(const std::string& path, const std::vector<std::string>& only_channels,
                        const std::function<void(std::size_t, Frame&&)>& each);
// The same, with facts(stack) called once before the first frame with the stack's shared facts
// (camera, bands, scene, what is known; no frames), which the caller may keep: what reads the
// frames as they come may need the camera.
Stack read_stack_frames(const std::string& path, const std::vector<std::string>& only_channels,
                        const std::function<void(const Stack&)>& facts,
                        const std::function<void(std::size_t, Frame&&)>& each);

// The channel names and bands of a stack, from its first header (no pixels read).
struct StackSummary {
  int frames = 0;
  int width = 0, height = 0;
  std::vector<std::string> bands;
  std::vector<std::string> channels;
  bool truth_known = true;  // as StackHeader
  bool site_known = true;
};
StackSummary peek_stack(const std::string& path);

// Header-only view: one line of truth per part and the stack's shared facts, for `skypol info`.
std::string describe_stack(const std::string& path);

// Every attribute of every part's header, as JSON (`skypol info --json`): numbers at full
// precision (%.17g), vectors and matrices as arrays, the truth included.
std::string describe_stack_json(const std::string& path);

}  // namespace skypol::stack
