// One raw mosaic from disk, as polarization camera SDKs and Python pipelines save it: an 8- or
// 16-bit single-channel PNG or TIFF (read with OpenImageIO, stack/oiio_module.h) or a NumPy .npy
// (stack/npy.h). Values are the integers stored (a 12-bit camera's 0..4095 in a 16-bit file);
// right_shift undoes SDKs that align them to the top of the 16 bits.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace skypol::stack {

struct RawFrame {
  int width = 0, height = 0;
  std::vector<double> values;  // row-major, as stored (npy floats kept as they are)
  // TIFF/EXIF DateTimeOriginal (or TIFF DateTime) as written, "YYYY:MM:DD HH:MM:SS", with
  // SubsecTimeOriginal appended as ".fff" when present; empty when the file has none (.npy).
  std::string exif_time;
};

// Throws SceneError naming the file: unreadable, more than one channel, a float image (PNG/TIFF),
// a .npy that is not two-dimensional.
RawFrame read_raw_frame(const std::string& path);

// The values as DN for the demosaic: shifted right by right_shift bits, each checked to be a
// whole number in [0, max_dn]; an error names the file, the pixel and the value (and suggests
// right_shift or the sensor's adc_bits when the value is too large).
std::vector<std::uint16_t> to_dn(const RawFrame& frame, const std::string& path, int right_shift, double max_dn);

}  // namespace skypol::stack
