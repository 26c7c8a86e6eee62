#include "render/frame.h"

#include <stdexcept>

namespace skypol::render {
namespace {
[[noreturn]] void missing(const std::map<std::string, std::vector<float>>& channels, const std::string& name) {
  std::string have;
  for (const auto& [k, v] : channels) have += " " + k;
  throw std::out_of_range("frame has no channel '" + name + "' (it has:" + (have.empty() ? " none" : have) + ")");
}
}  // namespace

const std::vector<float>& Frame::channel(const std::string& name) const {
  auto it = channels.find(name);
  if (it == channels.end()) missing(channels, name);
  return it->second;
}

std::vector<float>& Frame::channel(const std::string& name) {
  auto it = channels.find(name);
  if (it == channels.end()) missing(channels, name);
  return it->second;
}

}  // namespace skypol::render
