// `skypol export`: a stack's frames as ordinary single-part files that OpenCV, NumPy, ImageMagick
// and GDAL open (a multi-part EXR opens in none of them; docs/exr-format.md). One file per frame
// (TIFF and PNG: per frame and channel, "….<channel>.<ext>" when several are asked for: OpenCV
// 4.6 opens no float TIFF of 2, 4 or 5 channels), named <stack stem>_<NNN>_<YYYYMMDDTHHMMSS>Z.<ext>
// so that the names sort in time order and carry the time; a times.csv (file,time) beside them
// lists every file, the form `skypol import` reads back.
#pragma once

#include <string>
#include <vector>

namespace skypol::stack {

struct ExportOptions {
  std::string format = "npy";  // exr, tiff, npy, png
  // Channels in this order: S0 S1 S2 S3 DoLP AoLP (of `band`), raw (the sensor's mosaic), mask,
  // or a full channel name as in the stack ("S0.R").
  std::vector<std::string> channels{"S0", "S1", "S2", "DoLP", "AoLP"};
  std::string band;            // empty: the stack's first band
  std::string out_dir = ".";
};

// The stack is read one frame at a time, each frame's files written before the next is read (the
// memory is one frame's); a frame that cannot be read or written removes the files already written.
// Pixel types: float32 everywhere (EXR, TIFF, NPY shape (rows, cols) or (rows, cols, channels)),
// except the raw mosaic alone, kept as uint16 DN in TIFF, NPY and PNG, as cameras save it. PNG
// holds integers: raw as DN, DoLP and mask scaled by 65535, AoLP mapped from (−90°, 90°] onto
// 0..65535; S0–S3 (radiances) are refused in PNG. TIFF and PNG carry the frame's UTC time as
// DateTime and Exif:DateTimeOriginal. Every file is written under a temporary name and renamed.
// Returns the files written. Throws SceneError naming the stack or file.
std::vector<std::string> export_stack(const std::string& stack_path, const ExportOptions& options);

}  // namespace skypol::stack
