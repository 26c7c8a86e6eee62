// The work on a sky that depends only on which of its pixels are valid and on a frame, made once
// per set of valid pixels, for the views of a stack (stack_sky.h): the AoLP sun fits, the sky
// masks and the disk filters. The views repeat it: a frame subset whose mask is the whole stack's
// reads the whole stack's masked sky (on a clear sky every subset's is: dofp8 masks no pixel); a
// sector view's mask leaves its sky as its judgments found it, so that its final sun fits are the
// judgments'; auto's sun_vector, sun_vector_ephemeris and sun_dolp run the same views, and
// invariance and great_circle filter the same masked frames. Thread-safe: each item is made once
// (call_once; the views' sub-runs run in parallel).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "skypole/e_vectors.h"
#include "skypole/sky_images.h"
#include "skypole/sky_mask.h"

namespace skypol::skypole {

class SkyMemo {
 public:
  class Entry;  // the work on one set of valid pixels

  // For a stack of `frames` frames.
  explicit SkyMemo(std::size_t frames);
  ~SkyMemo();
  SkyMemo(const SkyMemo&) = delete;
  SkyMemo& operator=(const SkyMemo&) = delete;

  // The entry of `sky`'s valid pixels (a hash of them, then the bitmaps compared): found once per
  // sky, then passed to the calls below.
  const Entry& on(const SkyImages& sky) const;
  // sun_from_aolp(sky, sky.dolp[t], ev, min_dolp, quality, robust) of stack frame f (the sky's
  // frame t; ev its E-vectors, e_vectors.h).
  std::optional<Eigen::Vector3d> aolp_sun(const Entry& on, const SkyImages& sky, std::size_t t, std::size_t f,
                                          const FrameEVectors& ev, double min_dolp, bool robust,
                                          double* quality) const;
  // The sky mask of the stack frames keep[f] = 1 (empty: all) judged on the entry's sky: make().
  SkyMask sky_mask(const Entry& on, const std::vector<std::uint8_t>& keep,
                   const std::function<SkyMask()>& make) const;
  // disk_filter(sky.dolp[t], sky, radius_px) of stack frame f, kept while fewer than twice the
  // stack's frames are (a memory that the sub-runs of a cloudy sky, each masked its own way, would
  // not repay; past it they are computed and not kept).
  std::vector<float> filtered(const Entry& on, const SkyImages& sky, std::size_t t, std::size_t f,
                              double radius_px) const;

 private:
  std::size_t frames_, budget_images_;
  mutable std::mutex mutex_;
  mutable std::vector<std::unique_ptr<Entry>> entries_;
  mutable std::size_t filtered_images_ = 0;  // kept by filtered()
};

}  // namespace skypol::skypole
