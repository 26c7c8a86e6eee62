// skypol_oiio.so: the OpenImageIO calls of the stack room, in a module that the executable loads
// only when a command needs them (stack/oiio_module.h says why).
#include <cerrno>
#include <cstring>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "stack/oiio_plugin/api.h"

namespace skypol::stack::oiio {
namespace {

OIIO::ImageBufAlgo::TextAlignX to_oiio(Align a) {
  switch (a) {
    case Align::Centre: return OIIO::ImageBufAlgo::TextAlignX::Center;
    case Align::Right: return OIIO::ImageBufAlgo::TextAlignX::Right;
    case Align::Left: break;
  }
  return OIIO::ImageBufAlgo::TextAlignX::Left;
}

std::string png(const std::string& path, int width, int height, float* rgb, const std::vector<Label>& labels,
                const Font& font) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT), rgb);
  for (const Label& t : labels) {
    // Without the font the picture is still right, only unlabelled.
    OIIO::ImageBufAlgo::render_text(buf, t.x, t.y, t.text, font.size_px, font.name,
                                    {font.rgb[0], font.rgb[1], font.rgb[2]}, to_oiio(t.align));
  }
  buf.set_write_format(OIIO::TypeDesc::UINT8);
  if (!buf.write(path, OIIO::TypeDesc::UINT8, "png")) {
    const std::string e = buf.geterror();
    return e.empty() ? "cannot write" : e;
  }
  return {};
}

std::string typed_image(const std::string& format_path, const std::string& open_path, int width, int height,
                        const std::vector<std::string>& channels, OIIO::TypeDesc type, const void* pixels,
                        const std::vector<std::pair<std::string, std::string>>& attributes) {
  OIIO::ImageSpec spec(width, height, static_cast<int>(channels.size()), type);
  spec.channelnames = channels;
  for (const auto& [name, value] : attributes) spec.attribute(name, value);
  auto out = OIIO::ImageOutput::create(format_path);
  if (!out) {
    const std::string e = OIIO::geterror();
    return e.empty() ? "no writer for this file type" : e;
  }
  if (!out->open(open_path, spec) || !out->write_image(type, pixels) || !out->close()) {
    // OpenImageIO keeps an open or write failure on the output object, not in its global error.
    std::string e = out->geterror();
    if (e.empty()) e = OIIO::geterror();
    if (e.empty()) e = std::strerror(errno);
    return e;
  }
  return {};
}

std::string float_image(const std::string& format_path, const std::string& open_path, int width, int height,
                        const std::vector<std::string>& channels, const float* pixels,
                        const std::vector<std::pair<std::string, std::string>>& attributes) {
  return typed_image(format_path, open_path, width, height, channels, OIIO::TypeDesc::FLOAT, pixels, attributes);
}

std::string u16_image(const std::string& format_path, const std::string& open_path, int width, int height,
                      const std::vector<std::string>& channels, const unsigned short* pixels,
                      const std::vector<std::pair<std::string, std::string>>& attributes) {
  return typed_image(format_path, open_path, width, height, channels, OIIO::TypeDesc::UINT16, pixels, attributes);
}

class OiioReader final : public Reader {
 public:
  explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {}
  bool seek(int part) override { return in_->seek_subimage(part, 0); }
  int width() const override { return in_->spec().width; }
  int height() const override { return in_->spec().height; }
  int nchannels() const override { return in_->spec().nchannels; }
  int channel_index(const std::string& name) const override { return in_->spec().channelindex(name); }
  std::string string_attribute(const std::string& name, const std::string& fallback) const override {
    return in_->spec().get_string_attribute(name, fallback);
  }
  float float_attribute(const std::string& name) const override { return in_->spec().get_float_attribute(name); }
  std::string pixel_format() const override { return in_->spec().format.c_str(); }
  bool read(int part, float* out) override {
    return in_->read_image(part, 0, 0, in_->spec().nchannels, OIIO::TypeDesc::FLOAT, out);
  }
  std::string error() override { return in_->geterror(); }

 private:
  std::unique_ptr<OIIO::ImageInput> in_;
};

std::unique_ptr<Reader> open_image(const std::string& path, std::string* error) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    if (error) *error = OIIO::geterror();
    return nullptr;
  }
  return std::make_unique<OiioReader>(std::move(in));
}

const Api kApi{kApiVersion, &png, &float_image, &u16_image, &open_image};

}  // namespace
}  // namespace skypol::stack::oiio

extern "C" __attribute__((visibility("default"))) const skypol::stack::oiio::Api* skypol_oiio_api() {
  return &skypol::stack::oiio::kApi;
}
