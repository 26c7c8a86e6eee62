// OpenImageIO, loaded only by the commands that draw or read images through it (PNG previews, the
// classic estimator's intermediate EXR). Debian's OpenImageIO brings ~250 shared libraries (GDAL,
// OpenCV, FFmpeg, …) whose loading cost every `skypol` start 0.3–0.5 s of CPU; the executable
// therefore never links it: skypol_oiio.so, built beside it, is dlopen'ed on first use.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace skypol::stack::oiio {

enum class Align { Left, Centre, Right };

// A line of text drawn onto a picture, anchored at its baseline.
struct Label {
  int x = 0, y = 0;
  std::string text;
  Align align = Align::Left;
};

struct Font {
  const char* name;  // e.g. "DejaVuSans"; without it installed the labels are skipped
  int size_px;
  float rgb[3];
};

// Interleaved RGB float pixels in [0, 1], labels drawn on them (in place), written as an 8-bit PNG at `path`.
// Returns an empty string on success, else OpenImageIO's error.
std::string write_png(const std::string& path, int width, int height, float* rgb,
                      const std::vector<Label>& labels, const Font& font);

// A float image of named interleaved channels, written at `open_path` in the format that
// `format_path`'s extension names, with string attributes. Empty on success, else the error.
std::string write_float_image(const std::string& format_path, const std::string& open_path, int width, int height,
                              const std::vector<std::string>& channels, const float* pixels,
                              const std::vector<std::pair<std::string, std::string>>& attributes);

// The same for 16-bit unsigned pixels (raw mosaics in DN, as camera SDKs save them in PNG or TIFF).
std::string write_u16_image(const std::string& format_path, const std::string& open_path, int width, int height,
                            const std::vector<std::string>& channels, const unsigned short* pixels,
                            const std::vector<std::pair<std::string, std::string>>& attributes);

// A multi-part image file read one part at a time (OpenImageIO's ImageInput, narrowed).
class Reader {
 public:
  virtual ~Reader() = default;
  virtual bool seek(int part) = 0;  // false past the last part
  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual int nchannels() const = 0;
  virtual int channel_index(const std::string& name) const = 0;  // -1 if absent
  virtual std::string string_attribute(const std::string& name, const std::string& fallback) const = 0;
  virtual float float_attribute(const std::string& name) const = 0;
  // The file's pixel type as OpenImageIO names it ("uint8", "uint16", "float", …): read() scales
  // unsigned integers to [0, 1], so an integer pixel is value·(2^bits − 1).
  virtual std::string pixel_format() const = 0;
  // All channels of `part` as interleaved floats into `out` (width·height·nchannels).
  virtual bool read(int part, float* out) = 0;
  virtual std::string error() = 0;
};

// Opens `path`, or returns null with the reason in `*error`.
std::unique_ptr<Reader> open(const std::string& path, std::string* error);

// Where the module is looked for, in order: $SKYPOL_OIIO_MODULE; skypol_oiio.so beside the running
// executable (/proc/self/exe); the build tree's copy. Loading failure throws std::runtime_error
// naming the paths tried.
std::string module_path();

}  // namespace skypol::stack::oiio
