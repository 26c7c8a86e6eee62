#include "stack/frame.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace skypol::stack {
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

void size_channel(std::vector<float>& channel, std::size_t n) {
  if (channel.size() == n) return;
  if (channel.capacity() >= n) {
    channel.resize(n);
    return;
  }
  std::vector<float> fresh;
  fresh.reserve(n);  // allocated, not yet touched
#if defined(MADV_HUGEPAGE)
  // Advise the 2 MiB-aligned interior before the first touch; the allocator's own alignment is
  // only 16 bytes. Advice only: where the kernel declines, 4 KiB pages are used as before.
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(fresh.data());
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + n * sizeof(float)) & ~(kHuge - 1);
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
  fresh.resize(n);
  std::copy(channel.begin(), channel.end(), fresh.begin());
  channel.swap(fresh);
}

const char* polarizer_angles_name(PolarizerAngles a) {
  switch (a) {
    case PolarizerAngles::calibrated: return "calibrated";
    case PolarizerAngles::nominal: return "nominal";
    case PolarizerAngles::none: break;
  }
  return "none";
}

std::optional<PolarizerAngles> polarizer_angles_named(std::string_view name) {
  for (const PolarizerAngles a : {PolarizerAngles::none, PolarizerAngles::calibrated, PolarizerAngles::nominal})
    if (name == polarizer_angles_name(a)) return a;
  return std::nullopt;
}

}  // namespace skypol::stack
