// Finds and loads skypol_oiio.so on first use (stack/oiio_module.h).
#include "stack/oiio_module.h"

#include <dlfcn.h>

#include <cstdlib>

#include <filesystem>
#include <mutex>
#include <stdexcept>

#include "stack/oiio_plugin/api.h"

namespace skypol::stack::oiio {
namespace {

namespace fs = std::filesystem;
constexpr const char* kModuleName = "skypol_oiio.so";

std::vector<std::string> candidates() {
  std::vector<std::string> paths;
  if (const char* env = std::getenv("SKYPOL_OIIO_MODULE"); env && *env) paths.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) paths.push_back((exe.parent_path() / kModuleName).string());
#ifdef SKYPOL_OIIO_MODULE_BUILD_PATH
  paths.emplace_back(SKYPOL_OIIO_MODULE_BUILD_PATH);
#endif
  return paths;
}

struct Loaded {
  const Api* api = nullptr;
  std::string path;
  std::string error;
};

const Loaded& loaded() {
  static const Loaded l = [] {
    Loaded r;
    std::string tried;
    for (const std::string& p : candidates()) {
      if (!fs::exists(p)) {
        tried += "\n  " + p + ": no such file";
        continue;
      }
      // RTLD_LOCAL: OpenImageIO's symbols stay out of the executable's namespace.
      void* h = dlopen(p.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!h) {
        tried += "\n  " + p + ": " + dlerror();
        continue;
      }
      auto entry = reinterpret_cast<const Api* (*)()>(dlsym(h, "skypol_oiio_api"));
      const Api* api = entry ? entry() : nullptr;
      if (!api || api->version != kApiVersion) {
        tried += "\n  " + p + ": not a skypol_oiio module of this build";
        continue;
      }
      r.api = api;
      r.path = p;
      return r;  // the handle stays open for the life of the process
    }
    r.error = std::string("cannot load OpenImageIO's module ") + kModuleName + " (set SKYPOL_OIIO_MODULE); tried:" + tried;
    return r;
  }();
  return l;
}

const Api& api() {
  const Loaded& l = loaded();
  if (!l.api) throw std::runtime_error(l.error);
  return *l.api;
}

}  // namespace

std::string write_png(const std::string& path, int width, int height, float* rgb, const std::vector<Label>& labels,
                      const Font& font) {
  return api().write_png(path, width, height, rgb, labels, font);
}

std::string write_float_image(const std::string& format_path, const std::string& open_path, int width, int height,
                              const std::vector<std::string>& channels, const float* pixels,
                              const std::vector<std::pair<std::string, std::string>>& attributes) {
  return api().write_float_image(format_path, open_path, width, height, channels, pixels, attributes);
}

std::string write_u16_image(const std::string& format_path, const std::string& open_path, int width, int height,
                            const std::vector<std::string>& channels, const unsigned short* pixels,
                            const std::vector<std::pair<std::string, std::string>>& attributes) {
  return api().write_u16_image(format_path, open_path, width, height, channels, pixels, attributes);
}

std::unique_ptr<Reader> open(const std::string& path, std::string* error) { return api().open(path, error); }

std::string module_path() {
  api();
  return loaded().path;
}

}  // namespace skypol::stack::oiio
