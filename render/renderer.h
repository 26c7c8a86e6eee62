// The tiled renderer: for each pixel, the camera's ray(s), the occluders' verdict and the sky's
// Stokes vector in the sensor frame, written as the channels a scene asks for.
//
// Camera rays do not change over a time series, so at 1 sample per pixel they are computed once
// per stack (with the occlusion test) as render/ray_planes.h's float planes of each row's span of
// sky-seeing pixels, and each frame costs only the sky evaluation over those spans (pixels outside
// them are zeros); a later stack with the same camera may reuse them (ray_planes()). With N > 1 samples per pixel the samples are stratified on an
// N-rooks pattern with a jitter seeded by (seed, pixel, sample), recomputed per frame. Output bytes
// do not depend on the thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "stack/frame.h"
#include "render/occluders.h"
#include "render/ray_planes.h"
#include "sky/sky_model.h"

namespace skypol::render {

struct RenderOptions {
  int spp = 1;
  std::uint64_t seed = 0;
  std::vector<std::string> bands{"Y"};
  // Which of S0, S1, S2, S3, DoLP, AoLP, mask to produce (per band where it applies).
  std::vector<std::string> channels{"S0", "S1", "S2", "DoLP", "AoLP", "mask"};
  int tile_rows = 16;
  // spp = 1: keep every pixel's ray for the frames to come (RayPlanes). false suits a one-frame
  // stack without occluders: each render traces its tiles' rays into per-thread scratch instead,
  // and no full-frame ray memory is ever allocated or faulted in (the output is the same).
  bool keep_rays = true;
  // spp = 1: a frame this renderer rendered last keeps its zeros outside the image circle, so
  // rendering into it again skips them (stack::Frame::zero_outside; 22 MB of stores a frame for
  // the paper's scene with DoLP and AoLP). Only for a caller whose frames nothing else writes in
  // between, other than what resets the token (the sensor stage does): render/pipeline.cpp.
  bool reuse_cleared = false;
};

// Channel names a frame will carry for these options ("S0.Y", …, "R", "G", "B", "mask").
std::vector<std::string> channel_names(const RenderOptions& options);

class Renderer {
 public:
  // occluders may be null (no occluders: no ray tracing at all). planes: the ray_planes() of an
  // earlier renderer with the same camera and tile_rows and no occluders, to skip computing them
  // again (ignored at spp > 1 or with occluders; std::invalid_argument if their size differs).
  Renderer(std::shared_ptr<const camera::Camera> camera, RenderOptions options,
           std::shared_ptr<const Occluders> occluders = nullptr,
           std::shared_ptr<const RayPlanes> planes = nullptr);

  // The channels of one frame (Truth is left default; the caller fills it).
  stack::Frame render(const sky::SkyModel& sky, const sky::Sun& sun) const;

  // The same into `frame`, whose channels become exactly channel_names(options()): storage of the
  // right size is reused, so a caller rendering a series into one frame allocates (and
  // page-faults) only once. Every value is rewritten; the frame's truth is left as it was.
  void render(const sky::SkyModel& sky, const sky::Sun& sun, stack::Frame& frame) const;

  // One sky model per band (skies[i] for options().bands[i], e.g. the VRTE sky's), or a single
  // model for every band (then exactly the calls above). Throws std::invalid_argument otherwise.
  stack::Frame render(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun) const;
  void render(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun, stack::Frame& frame) const;

  // Rows [y0, y1) of that frame into `band`, a frame of width × (y1 − y0) pixels with the same
  // channels (storage reused as by render(…, frame)), pixel for pixel the bytes of those rows of the
  // whole frame: for writing a part band by band from memory that stays in cache
  // (stack::write_stack_banded). spp = 1 only (std::logic_error otherwise).
  void render_rows(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun, int y0, int y1,
                   stack::Frame& band) const;

  // A frame with every channel allocated (zeros), for render(sky, sun, frame): lets a caller pay
  // for the memory before timing or rendering starts.
  stack::Frame new_frame() const;

  const camera::Camera& camera() const { return *camera_; }
  const RenderOptions& options() const { return options_; }
  // The per-stack rays (spp = 1 and kept only; null otherwise), shareable with a later Renderer.
  const std::shared_ptr<const RayPlanes>& ray_planes() const { return planes_; }

 private:
  // Samples of rows [y0, y1): rays[k] and weight[k] (1 where the sample sees the sky, 0 outside
  // the image circle or occluded), k = (pixel in tile)·spp + sample. surface_s0, if not empty,
  // receives the S0 of the occluder each sample meets (shaded occluders; 0 elsewhere).
  void trace_tile(int y0, int y1, std::span<sky::ViewRay> rays, std::span<float> weight,
                  std::span<float> surface_s0 = {}) const;
  // Shaded occluders at spp > 1: surface_s0_ as the mean over each pixel's samples.
  void shade_sampled();
  // Throws unless there is one sky model, or one per band.
  void check_skies(std::span<const sky::SkyModel* const> skies) const;
  void render_cached(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun, stack::Frame& frame, int first,
                     int last) const;
  void render_sampled(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun, stack::Frame& frame) const;

  std::shared_ptr<const camera::Camera> camera_;
  RenderOptions options_;
  std::shared_ptr<const Occluders> occluders_;

  // spp = 1: the rays of each row's span of pixels that may see the sky.
  std::shared_ptr<const RayPlanes> planes_;

  // Shaded occluders only: per pixel, the mean S0 of the occluder surfaces its samples meet
  // (unpolarized, added to S0 of every frame before DoLP and AoLP). Empty otherwise.
  std::vector<float> surface_s0_;

  // Rays traced per tile (no planes_): each row's span as a render traced it, x0 | x1 << 32, or -1
  // before any did, so that a band frame reused for other rows is cleared only where the old
  // rows' spans were wider (render_rows). Relaxed atomics: every render traces the same spans,
  // and a render reads only rows that an earlier one finished.
  std::unique_ptr<std::atomic<std::int64_t>[]> traced_spans_;

  // This renderer's stack::Frame::zero_outside token (shifted left 32 bits and or-ed with the
  // first row rendered): unique in the process, never 0.
  std::uint64_t token_;
};

}  // namespace skypol::render
