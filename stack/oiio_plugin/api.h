// The table of functions that skypol_oiio.so exports to stack/oiio_module.cpp. Both sides are
// built from this tree with the same compiler, so C++ types cross the boundary; the version
// guards against a stale module beside a newer executable.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "stack/oiio_module.h"

namespace skypol::stack::oiio {

inline constexpr int kApiVersion = 2;

struct Api {
  int version;
  std::string (*write_png)(const std::string& path, int width, int height, float* rgb,
                           const std::vector<Label>& labels, const Font& font);
  std::string (*write_float_image)(const std::string& format_path, const std::string& open_path, int width,
                                   int height, const std::vector<std::string>& channels, const float* pixels,
                                   const std::vector<std::pair<std::string, std::string>>& attributes);
  std::string (*write_u16_image)(const std::string& format_path, const std::string& open_path, int width,
                                 int height, const std::vector<std::string>& channels, const unsigned short* pixels,
                                 const std::vector<std::pair<std::string, std::string>>& attributes);
  std::unique_ptr<Reader> (*open)(const std::string& path, std::string* error);
};

}  // namespace skypol::stack::oiio

// The module's one exported symbol.
extern "C" const skypol::stack::oiio::Api* skypol_oiio_api();
