// `skypol import`: raw polarization frames from a real camera into the stack format, so that the
// estimators run on them as on a rendered stack. A capture file (TOML, docs/import.md) lists the
// frames, where their times come from, the site when known, the camera's [camera] and [sensor]
// sections exactly as a scene writes them (the lens, its calibration, the attitude; the polarizer
// mosaic, colour filter, black level and gains), and optional dark and flat frames. Each frame
// goes through the same demosaic as the renderer's sensor stage (camera/dofp_sensor.h), and the
// stack is written with its truth marked unknown (stack/stack_io.h, StackHeader::truth_known).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "scene/scene_source.h"

namespace skypol::stack {

struct ImportReport {
  std::size_t frames = 0;
  int width = 0, height = 0;
  std::vector<std::string> bands;
  bool site_known = false;
};

// Reads the capture file and every frame, then writes the stack at out_path (temporary name,
// renamed when complete). Errors are SceneError at the capture file's key, a frame's file, or the
// times CSV's line; nothing is written before every frame has been read and checked.
// progress(done, total) is called as frames are converted (may be empty).
ImportReport import_capture(const std::string& capture_path, const std::string& out_path,
                            const std::vector<scene::Override>& overrides = {},
                            const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace skypol::stack
