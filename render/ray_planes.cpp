#include "render/ray_planes.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <stdexcept>

#include <sys/mman.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "render/occlusion_pass.h"

namespace skypol::render {
namespace {

// n floats, uninitialised (new[] of a large size maps fresh pages and touches none of them), their
// 2 MiB-aligned interior advised for huge pages (Linux; advice only): a page is faulted in, and
// zeroed by the kernel, only when a block is written into it.
std::unique_ptr<float[]> untouched_floats(std::size_t n) {
  std::unique_ptr<float[]> p(new float[n]);
#if defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(p.get());
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + n * sizeof(float)) & ~(kHuge - 1);
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
  return p;
}

}  // namespace

void TileRays::trace(const camera::Camera& camera, int y0, int y1, const Occluders* occluders, float* surface_s0) {
  const std::size_t w = static_cast<std::size_t>(camera.width());
  const std::size_t count = static_cast<std::size_t>(y1 - y0) * w;
  y0_ = y0;
  planes_.resize(7 * count);
  float* p[7];
  for (std::size_t c = 0; c < 7; ++c) p[c] = planes_.data() + c * count;
  for (int y = y0; y < y1; ++y) {
    const std::size_t at = static_cast<std::size_t>(y - y0) * w;
    camera.ray_row(y, 0, w, {p[0] + at, p[1] + at, p[2] + at, p[3] + at, p[4] + at, p[5] + at, p[6] + at});
  }
  if (occluders) {
    rays_.resize(count);
    for (std::size_t k = 0; k < count; ++k) rays_[k] = {{p[0][k], p[1][k], p[2][k]}, {p[3][k], p[4][k], p[5][k]}};
    apply_occluders(*occluders, rays_, std::span(p[6], count),
                    surface_s0 ? std::span(surface_s0, count) : std::span<float>{});
  }
  // Trim the weight-0 pixels at both ends of each row (outside the image circle), keeping those
  // that show a shaded occluder.
  rows_.resize(static_cast<std::size_t>(y1 - y0));
  for (int y = y0; y < y1; ++y) {
    const std::size_t at = static_cast<std::size_t>(y - y0) * w;
    const float* weight = p[6] + at;
    const float* lit = surface_s0 ? surface_s0 + at : nullptr;
    auto dark = [&](std::size_t x) { return weight[x] == 0 && (!lit || lit[x] == 0); };
    std::size_t x0 = 0, x1 = w;
    while (x0 < x1 && dark(x0)) ++x0;
    while (x1 > x0 && dark(x1 - 1)) --x1;
    const std::size_t q = at + x0;
    rows_[static_cast<std::size_t>(y - y0)] = {static_cast<int>(x0), static_cast<int>(x1), p[0] + q, p[1] + q,
                                               p[2] + q, p[3] + q, p[4] + q, p[5] + q, p[6] + q};
  }
}

RayPlanes::RayPlanes(const camera::Camera& camera, int tile_rows, const Occluders* occluders,
                     std::vector<float>* surface_s0)
    : width_(camera.width()), height_(camera.height()), tile_rows_(tile_rows) {
  if (tile_rows_ < 1) throw std::invalid_argument("ray planes: tile_rows must be >= 1");
  const std::size_t w = static_cast<std::size_t>(width_);
  const int h = height_, tiles = (h + tile_rows_ - 1) / tile_rows_;
  blocks_.resize(static_cast<std::size_t>(tiles));
  spans_.resize(static_cast<std::size_t>(h));
  memory_ = untouched_floats(7 * w * static_cast<std::size_t>(h));
  ones_.assign(w, 1.0f);
  std::atomic<std::size_t> used{0};
  // Full-width rays of one tile, then its spans copied into the tile's block.
  tbb::enumerable_thread_specific<TileRays> scratch;
  tbb::parallel_for(0, tiles, [&](int t) {
    TileRays& tile = scratch.local();
    const int y0 = t * tile_rows_, y1 = std::min(h, y0 + tile_rows_);
    tile.trace(camera, y0, y1, occluders, surface_s0 ? surface_s0->data() + static_cast<std::size_t>(y0) * w : nullptr);
    std::size_t stored = 0;
    for (int y = y0; y < y1; ++y) {
      const Row r = tile.row(y);
      spans_[static_cast<std::size_t>(y)] = {r.x0, r.x1, stored};
      stored += static_cast<std::size_t>(r.x1 - r.x0);
    }
    // A tile whose spans see the sky at every pixel (no occluders, a convex image circle: the
    // usual case) stores no weight plane; its rows point at ones_ instead (a seventh less memory
    // to fault in).
    bool all_ones = true;
    for (int y = y0; y < y1 && all_ones; ++y) {
      const Row r = tile.row(y);
      all_ones = std::all_of(r.weight, r.weight + (r.x1 - r.x0), [](float v) { return v == 1.0f; });
    }
    Block& b = blocks_[static_cast<std::size_t>(t)];
    b.count = stored;
    b.ones = all_ones;
    const std::size_t planes = all_ones ? 6 : 7;
    b.data = memory_.get() + used.fetch_add(planes * stored);
    for (int y = y0; y < y1; ++y) {
      const Row r = tile.row(y);
      const Span& s = spans_[static_cast<std::size_t>(y)];
      const std::size_t len = static_cast<std::size_t>(s.x1 - s.x0);
      const float* from[7] = {r.dx, r.dy, r.dz, r.ux, r.uy, r.uz, r.weight};
      for (std::size_t c = 0; c < planes; ++c) std::copy_n(from[c], len, b.data + c * stored + s.offset);
    }
  });
}

RayPlanes::Row RayPlanes::row(int y) const {
  const Span& s = spans_[static_cast<std::size_t>(y)];
  const Block& b = blocks_[static_cast<std::size_t>(y / tile_rows_)];
  const float* base = b.data + s.offset;
  const std::size_t n = b.count;
  return {s.x0, s.x1, base, base + n, base + 2 * n, base + 3 * n, base + 4 * n, base + 5 * n,
          b.ones ? ones_.data() : base + 6 * n};
}

std::size_t RayPlanes::stored_pixels() const {
  std::size_t n = 0;
  for (const Block& b : blocks_) n += b.count;
  return n;
}

}  // namespace skypol::render
