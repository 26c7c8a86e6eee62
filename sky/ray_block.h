// Blocks of ViewRays in structure-of-arrays form, for the models' many-directions paths.
// Why: ViewRay is 6 floats (d, e0), and GCC 12 does not vectorize loads with a stride of 6; copied
// into six float arrays of a small block, the model's loop vectorizes (the speed-up measured:
// docs/calibration-history.md, "Measurements behind the code's constants"). An internal helper of
// sky/, not part of the renderer's interface.
#pragma once

#include <cstddef>
#include <span>

#include "sky/sky_model.h"

namespace skypol::sky::detail {

struct RayBlock {
  static constexpr std::size_t kSize = 128;  // 3 KiB: stays in L1 next to the output
  std::size_t first = 0;                     // index of the block's first ray in the span
  std::size_t count = 0;                     // ≤ kSize
  alignas(32) float dx[kSize], dy[kSize], dz[kSize];  // view direction d
  alignas(32) float ux[kSize], uy[kSize], uz[kSize];  // basis vector e0
};

// Calls kernel(const RayBlock&) for consecutive blocks covering all of `rays`.
template <class Kernel>
void for_each_ray_block(std::span<const ViewRay> rays, Kernel&& kernel) {
  RayBlock b;
  for (std::size_t first = 0; first < rays.size(); first += RayBlock::kSize) {
    b.first = first;
    b.count = rays.size() - first < RayBlock::kSize ? rays.size() - first : RayBlock::kSize;
    for (std::size_t j = 0; j < b.count; ++j) {
      const ViewRay& r = rays[first + j];
      b.dx[j] = r.d.x();
      b.dy[j] = r.d.y();
      b.dz[j] = r.d.z();
      b.ux[j] = r.e0.x();
      b.uy[j] = r.e0.y();
      b.uz[j] = r.e0.z();
    }
    kernel(static_cast<const RayBlock&>(b));
  }
}

}  // namespace skypol::sky::detail
