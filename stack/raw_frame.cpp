#include "stack/raw_frame.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "scene/scene_error.h"
#include "stack/npy.h"
#include "stack/oiio_module.h"

namespace skypol::stack {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw scene::SceneError(scene::FileLoc{path, 0, 0}, what);
}

RawFrame read_npy_frame(const std::string& path) {
  NpyArray a;
  try {
    a = read_npy(path);
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    fail(path, m.substr(std::min(m.size(), path.size() + 2)));  // read_npy's message starts with the path
  }
  if (a.shape.size() != 2) {
    fail(path, "a raw frame is a two-dimensional array (rows, columns); this one has " +
                   std::to_string(a.shape.size()) + " dimension(s)");
  }
  RawFrame f;
  f.height = static_cast<int>(a.shape[0]);
  f.width = static_cast<int>(a.shape[1]);
  f.values = std::move(a.values);
  return f;
}

RawFrame read_image_frame(const std::string& path) {
  std::string error;
  std::unique_ptr<oiio::Reader> in = oiio::open(path, &error);
  if (!in) fail(path, "cannot read (" + (error.empty() ? std::string("unknown format") : error) + ")");
  if (in->nchannels() != 1) {
    fail(path, "a raw mosaic has one channel; this image has " + std::to_string(in->nchannels()) +
                   " (save the sensor's raw output, not a demosaiced or colour picture)");
  }
  const std::string format = in->pixel_format();
  double full = 0;  // read() gives unsigned integers as value / full
  if (format == "uint8") full = 255;
  if (format == "uint16") full = 65535;
  if (full == 0) fail(path, "pixels are " + format + "; a raw mosaic is 8- or 16-bit unsigned integers");
  RawFrame f;
  f.width = in->width();
  f.height = in->height();
  std::vector<float> px(static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height));
  if (!in->read(0, px.data())) fail(path, "cannot read the pixels (" + in->error() + ")");
  f.values.resize(px.size());
  // float holds v/65535 to 24 bits, so rounding recovers the integer exactly.
  for (std::size_t i = 0; i < px.size(); ++i) f.values[i] = std::round(static_cast<double>(px[i]) * full);
  f.exif_time = in->string_attribute("Exif:DateTimeOriginal", "");
  if (f.exif_time.empty()) f.exif_time = in->string_attribute("DateTime", "");
  const std::string subsec = in->string_attribute("Exif:SubsecTimeOriginal", "");
  if (!f.exif_time.empty() && !subsec.empty()) f.exif_time += "." + subsec;
  return f;
}

}  // namespace

RawFrame read_raw_frame(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) fail(path, "no such file");
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".npy" ? read_npy_frame(path) : read_image_frame(path);
}

std::vector<std::uint16_t> to_dn(const RawFrame& frame, const std::string& path, int right_shift, double max_dn) {
  std::vector<std::uint16_t> dn(frame.values.size());
  const double div = std::ldexp(1.0, right_shift);
  for (std::size_t i = 0; i < dn.size(); ++i) {
    const double v = frame.values[i] / div;
    if (!(v >= 0 && v <= max_dn && v == std::floor(v))) {
      const std::size_t w = static_cast<std::size_t>(frame.width);
      char where[96];
      std::snprintf(where, sizeof where, "pixel (%zu, %zu) holds %.9g", i % w, i / w, frame.values[i]);
      std::string why = std::string(where) + ", not a whole number of DN in [0, " + std::to_string(static_cast<long>(max_dn)) + "]";
      if (v > max_dn) why += " (set [sensor] adc_bits to the camera's bit depth, or [capture] right_shift if the SDK "
                             "aligns values to the top bits)";
      fail(path, why);
    }
    dn[i] = static_cast<std::uint16_t>(v);
  }
  return dn;
}

}  // namespace skypol::stack
