#include "render/occlusion_pass.h"

#include <cstdint>
#include <vector>

namespace skypol::render {

void apply_occluders(const Occluders& occluders, std::span<const sky::ViewRay> rays, std::span<float> weight,
                     std::span<float> surface_s0) {
  std::vector<Eigen::Vector3f> dirs;
  std::vector<std::uint32_t> index;
  dirs.reserve(rays.size());
  index.reserve(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (weight[i] > 0) {
      dirs.push_back(rays[i].d);
      index.push_back(static_cast<std::uint32_t>(i));
    }
  }
  std::vector<std::uint8_t> hit(dirs.size());
  occluders.occluded(dirs, hit);
  for (float& s : surface_s0) s = 0;
  std::size_t hits = 0;
  for (std::size_t j = 0; j < dirs.size(); ++j) {
    if (!hit[j]) continue;
    weight[index[j]] = 0;
    // Compact the hit rays to the front for the shading pass.
    dirs[hits] = dirs[j];
    index[hits++] = index[j];
  }
  if (surface_s0.empty() || !occluders.shaded() || hits == 0) return;
  std::vector<float> s0(hits);
  occluders.surface_s0(std::span(dirs).first(hits), s0);
  for (std::size_t j = 0; j < hits; ++j) surface_s0[index[j]] = s0[j];
}

}  // namespace skypol::render
