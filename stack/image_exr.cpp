// Single-part float EXR of named channels (image_exr.h).
#include "stack/image_exr.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <unistd.h>

namespace skypol::stack {

void write_image_exr(const std::string& path, int width, int height,
                     const std::map<std::string, std::vector<float>>& channels,
                     const std::string& comment) {
  if (channels.empty()) throw std::invalid_argument("write_image_exr: no channels for " + path);
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (width <= 0 || height <= 0) throw std::invalid_argument("write_image_exr: empty image " + path);
  std::map<std::string, std::vector<float>> clean;
  for (const auto& [name, v] : channels) {
    if (v.size() != n)
      throw std::invalid_argument("write_image_exr: channel " + name + " has " +
                                  std::to_string(v.size()) + " values, expected " +
                                  std::to_string(n));
    std::vector<float>& c = clean[name];
    c.resize(n);
    for (std::size_t i = 0; i < n; ++i) c[i] = std::isfinite(v[i]) ? v[i] : 0.0f;
  }
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  if (!comment.empty()) header.insert("comments", Imf::StringAttribute(comment));
  Imf::FrameBuffer fb;
  for (auto& [name, v] : clean) {
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(v.data()), sizeof(float),
                               sizeof(float) * static_cast<std::size_t>(width)));
  }
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  try {
    Imf::OutputFile file(tmp.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(height);
  } catch (const std::exception& e) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write " + path + ": " + e.what());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write " + path + ": " + ec.message());
  }
}

}  // namespace skypol::stack
