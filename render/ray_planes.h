// The camera rays of a stack at 1 sample per pixel, computed once and kept as float planes for
// every frame: only each row's span of pixels that may see the sky is stored (about 45 % of the
// sensor for the paper's 185° fisheye), in one block per tile of rows, so a stack allocates and
// first-touches (page-faults) less than half of full-frame planes. Immutable once built: a sweep
// shares one RayPlanes between the stacks of a variant that keeps the camera (render/pipeline.cpp).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "camera/camera.h"
#include "render/occluders.h"
#include "sky/sky_model.h"

namespace skypol::render {

// Pixels of a row in [x0, x1): the ray of pixel x at index x − x0 of each plane. Outside the
// span every pixel has weight 0 and no shaded occluder.
struct RayRow {
  int x0 = 0, x1 = 0;
  const float *dx, *dy, *dz, *ux, *uy, *uz;
  const float* weight;  // 1 where the pixel sees the sky, 0 outside the image circle or occluded
};

// The rays of one tile of rows, traced into storage that the next trace() reuses: how RayPlanes
// is built, and how a one-frame render goes without planes at all (nothing to keep, so no
// full-frame memory to fault in).
class TileRays {
 public:
  // Rows [y0, y1) of `camera`, occlusion-tested when occluders is not null; surface_s0, if not
  // null, holds (y1 − y0)·width floats for the shaded occluders' S0 (render/occlusion_pass.h).
  void trace(const camera::Camera& camera, int y0, int y1, const Occluders* occluders, float* surface_s0 = nullptr);
  RayRow row(int y) const { return rows_[static_cast<std::size_t>(y - y0_)]; }

 private:
  int y0_ = 0;
  std::vector<float> planes_;  // 7 planes of (y1 − y0)·width: dx dy dz ux uy uz weight
  std::vector<sky::ViewRay> rays_;
  std::vector<RayRow> rows_;
};

class RayPlanes {
 public:
  using Row = RayRow;

  // Traces every pixel centre of `camera` in tiles of tile_rows rows (TBB), with the occlusion
  // test when occluders is not null. surface_s0, if not null, must hold width·height floats and
  // receives the shaded occluders' S0 per pixel (render/occlusion_pass.h).
  RayPlanes(const camera::Camera& camera, int tile_rows, const Occluders* occluders,
            std::vector<float>* surface_s0 = nullptr);

  Row row(int y) const;
  int width() const { return width_; }
  int height() const { return height_; }
  int tile_rows() const { return tile_rows_; }
  std::size_t stored_pixels() const;  // pixels inside the spans, summed over rows

 private:
  struct Block {
    float* data = nullptr;  // 7 planes of `count` floats: dx dy dz ux uy uz weight, in memory_
    std::size_t count = 0;
    bool ones = false;      // every weight is 1: the weight plane is not stored (rows point at ones_)
  };
  std::vector<float> ones_;  // width ones
  // One reservation of full-frame size, advised for huge pages; tiles take their blocks from its
  // start as they finish, so only the stored spans are ever touched.
  std::unique_ptr<float[]> memory_;
  struct Span {
    int x0 = 0, x1 = 0;
    std::size_t offset = 0;  // of the row's first stored pixel within its tile's block
  };
  int width_ = 0, height_ = 0, tile_rows_ = 1;
  std::vector<Block> blocks_;  // one per tile
  std::vector<Span> spans_;    // one per row
};

}  // namespace skypol::render
