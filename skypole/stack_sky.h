// A stack prepared once for an estimate and its jackknives (uncertainty.h). Each answer runs its
// method a dozen times more, without each frame group and without each sky sector; run on copies
// of the stack (frames_kept, sector_left_out), each of those sub-runs would copy the stack, prepare
// its sky, judge the sky mask and turn every pixel's AoLP into an E-vector again, at some fifteen
// times the cost of the answer alone (docs/calibration-history.md).
//
// Here the stack is read once (StackSky: read_sky_frames, sky_images.h), and each frame's E-vectors
// (e_vectors.h) and sky-mask judgments (sky_mask.h) are computed once, on the whole stack's sky. A
// sub-run is a SkyView: the frames it keeps, or the sector it leaves out, of a StackSky. Its prepared
// sky follows from each frame's usable pixels (sky_of); its mask, when its sky's valid pixels are
// the whole stack's (a frame subset, as a rule), from the kept frames' judgments by a count; its
// sun fits read the cached E-vectors. What genuinely depends on the subset is recomputed: the sun
// fits on its own masked sky, and the judgments of a sky without a sector (their suns are fitted on
// it) or of frames whose usable pixels differ. A view's answers are bit-identical to the runs on the
// copies (tests/skypole/stack_sky_test.cpp). What views repeat of each other (a fit, a mask, a
// filter on the same valid pixels) is made once too (sky_memo.h).
//
// Thread-safe: views of one StackSky may run in parallel (each cached part is made once).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "stack/frame.h"
#include "skypole/e_vectors.h"
#include "skypole/estimate.h"
#include "skypole/sky_images.h"
#include "skypole/sky_mask.h"
#include "skypole/sky_memo.h"

namespace skypol::skypole {

class StackSky {
 public:
  // `stack` must outlive this.
  StackSky(const stack::Stack& stack, const InputOptions& input);
  StackSky(const StackSky&) = delete;
  StackSky& operator=(const StackSky&) = delete;

  const stack::Stack& stack() const { return stack_; }
  const InputOptions& input() const { return input_; }
  // read_sky_frames(stack, input, …), read once; throws what prepare_sky_images(stack, input,
  // min_frames, method) would throw.
  const SkyFrames& frames(std::size_t min_frames, std::string_view method) const;
  // prepare_sky_images(stack, input, min_frames, method), prepared once (likewise).
  const SkyImages& sky(std::size_t min_frames, std::string_view method) const;
  // sky(), if it has been prepared; else nullptr.
  const SkyImages* sky_if_prepared() const;
  // judge_sky of sky() and every frame, once. Needs sky_if_prepared().
  const SkyJudgments& judgments() const;
  // Stack frame f's E-vectors on sky() at DoLP ≥ kEVectorMinDolp (nullptr when the frame has no AoLP
  // channel of the band), once. Needs sky_if_prepared().
  const FrameEVectors* e_vectors(std::size_t f) const;
  static constexpr double kEVectorMinDolp = kMaskMinDolp;  // the sky mask's and sun_vector's threshold

  // The work made once per set of valid pixels (sky_memo.h): fits, masks, filters.
  const SkyMemo& memo() const { return memo_; }

 private:
  const stack::Stack& stack_;
  InputOptions input_;
  mutable std::once_flag read_once_, sky_once_, judged_once_;
  mutable std::optional<SkyFrames> frames_;
  mutable std::optional<SkyImages> sky_;
  mutable std::optional<SkyJudgments> judgments_;
  mutable std::unique_ptr<std::once_flag[]> e_once_;
  mutable std::vector<std::optional<FrameEVectors>> e_vectors_;
  SkyMemo memo_;
};

// One run's view of a StackSky: the whole stack, the frames a frame jackknife keeps, or the stack
// with a sky sector left out in every frame (what run_method's jackknives rerun on).
class SkyView {
 public:
  explicit SkyView(const StackSky& whole);
  // The frames whose keep[i] is 1 (as frames_kept).
  static SkyView kept(const StackSky& whole, std::vector<std::uint8_t> keep);
  // Sector g of `sectors` about centre_px masked (as sector_left_out).
  static SkyView without_sector(const StackSky& whole, const Eigen::Vector2d& centre_px, int g, int sectors);

  const StackSky& source() const { return *source_; }
  const stack::Stack& stack() const { return source_->stack(); }
  const InputOptions& input() const { return source_->input(); }
  const FrameRefs& frames() const { return frames_; }
  bool is_whole() const { return keep_.empty() && left_out_.empty(); }
  // What the view stands for as a stack of its own: frames_kept or sector_left_out (uncertainty.h),
  // a copy, for a method that reads only stacks and for the tests that compare the two.
  stack::Stack copy() const;

  // prepare_sky_images of the view's stack (throws as it does).
  SkyImages prepared(std::size_t min_frames, std::string_view method) const;
  // compute_sky_mask of `prepared` (this view's prepared sky) and the view's frames.
  SkyMask sky_mask(const SkyImages& prepared, const SkyMaskParams& p = {}) const;
  // Each view frame's cached E-vectors, usable on `prepared` and any of its masks; nullptr where
  // there are none (no AoLP channel, or `prepared` has pixels the whole stack's sky lacks).
  std::vector<const FrameEVectors*> e_vectors(const SkyImages& prepared) const;
  // Each view frame's sun_from_aolp on `sky` (the prepared sky or a mask of it) with `ev` (e_vectors
  // of the prepared sky), from the memo (sky_memo.h) where ev has them. quality (optional)
  // receives each fit's quality, 1 where it found no sun.
  std::vector<std::optional<Eigen::Vector3d>> aolp_suns(const SkyImages& sky, const std::vector<const FrameEVectors*>& ev,
                                                        double min_dolp, bool robust,
                                                        std::vector<double>* quality = nullptr) const;
  // filter_all(sky, radius_px), from the memo when `sky`'s valid pixels are among the whole stack's.
  std::vector<std::vector<float>> filtered(const SkyImages& sky, double radius_px) const;

 private:
  SkyView(const StackSky& whole, std::vector<std::uint8_t> keep, std::vector<std::uint8_t> left_out);
  // Whether the valid pixels of `sky` (this view's prepared sky, or a mask of it) are among the
  // whole stack's sky's (and that is prepared).
  bool within_whole(const SkyImages& sky) const;

  const StackSky* source_;
  std::vector<std::uint8_t> keep_;      // empty: every frame
  std::vector<std::uint8_t> left_out_;  // empty: no pixel
  Eigen::Vector2d centre_px_ = Eigen::Vector2d::Zero();  // the left-out sector's (without_sector)
  int sector_ = -1, sectors_ = 0;
  std::vector<std::size_t> index_;      // the view's frames' indices in the stack
  FrameRefs frames_;
};

}  // namespace skypol::skypole
