// A stack prepared once for an estimate and its jackknives (stack_sky.h).
#include "skypole/stack_sky.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "skypole/uncertainty.h"

namespace skypol::skypole {

StackSky::StackSky(const stack::Stack& stack, const InputOptions& input)
    : stack_(stack),
      input_(input),
      e_once_(std::make_unique<std::once_flag[]>(stack.frames.size())),
      e_vectors_(stack.frames.size()) {}

const SkyFrames& StackSky::frames(std::size_t min_frames, std::string_view method) const {
  // Read once, under whichever method asks first; a method that cannot use the stack is told in its
  // own words by reading it again (the checks come in prepare_sky_images' order).
  std::call_once(read_once_, [&] {
    try {
      tbb::this_task_arena::isolate([&] { frames_.emplace(read_sky_frames(stack_, input_, 1, method)); });
    } catch (const std::invalid_argument&) {
    }
  });
  if (!frames_ || stack_.frames.size() < min_frames) {
    (void)read_sky_frames(stack_, input_, min_frames, method);
    throw std::logic_error("StackSky: a stack read once failed and then did not");
  }
  return *frames_;
}

const SkyImages& StackSky::sky(std::size_t min_frames, std::string_view method) const {
  const SkyFrames& f = frames(min_frames, method);
  std::call_once(sky_once_, [&] {
    try {
      sky_.emplace(sky_of(f, nullptr, nullptr, 1, method));
    } catch (const std::invalid_argument&) {
    }
  });
  if (!sky_) {
    (void)sky_of(f, nullptr, nullptr, min_frames, method);
    throw std::logic_error("StackSky: a sky prepared once failed and then did not");
  }
  return *sky_;
}

const SkyImages* StackSky::sky_if_prepared() const { return sky_ ? &*sky_ : nullptr; }

const FrameEVectors* StackSky::e_vectors(std::size_t f) const {
  const SkyImages& sky = *sky_;
  const auto it = stack_.frames[f].channels.find("AoLP." + sky.band);
  if (it == stack_.frames[f].channels.end() || it->second.size() != sky.pixels()) return nullptr;
  std::call_once(e_once_[f], [&] {
    e_vectors_[f].emplace(
        frame_e_vectors(sky, sky.dolp[f], it->second, stack_.camera->transport(), kEVectorMinDolp));
  });
  return &*e_vectors_[f];
}

const SkyJudgments& StackSky::judgments() const {
  std::call_once(judged_once_, [&] {
    // Isolated: a thread that waits here for its loops must not take up another view's work, which
    // may wait on this same once_flag.
    tbb::this_task_arena::isolate([&] {
      std::vector<const FrameEVectors*> ev(stack_.frames.size());
      tbb::parallel_for(std::size_t{0}, ev.size(), [&](std::size_t f) { ev[f] = e_vectors(f); });
      judgments_.emplace(judge_sky(*sky_, all_frames(stack_), *stack_.camera, SkyMaskParams{}, &ev));
    });
  });
  return *judgments_;
}

SkyView::SkyView(const StackSky& whole) : SkyView(whole, {}, {}) {}

SkyView::SkyView(const StackSky& whole, std::vector<std::uint8_t> keep, std::vector<std::uint8_t> left_out)
    : source_(&whole), keep_(std::move(keep)), left_out_(std::move(left_out)) {
  const stack::Stack& s = whole.stack();
  for (std::size_t i = 0; i < s.frames.size(); ++i)
    if (keep_.empty() || keep_[i]) {
      index_.push_back(i);
      frames_.push_back(&s.frames[i]);
    }
}

SkyView SkyView::kept(const StackSky& whole, std::vector<std::uint8_t> keep) {
  keep.resize(whole.stack().frames.size(), 0);
  return SkyView(whole, std::move(keep), {});
}

SkyView SkyView::without_sector(const StackSky& whole, const Eigen::Vector2d& centre_px, int g, int sectors) {
  const camera::Camera& camera = *whole.stack().camera;
  std::vector<std::uint8_t> left_out = sector_map(camera.width(), camera.height(), centre_px, sectors);
  for (std::uint8_t& s : left_out) s = s == g ? 1 : 0;
  SkyView view(whole, {}, std::move(left_out));
  view.centre_px_ = centre_px;
  view.sector_ = g;
  view.sectors_ = sectors;
  return view;
}

stack::Stack SkyView::copy() const {
  if (!keep_.empty()) return frames_kept(stack(), keep_);
  if (!left_out_.empty()) return sector_left_out(stack(), centre_px_, sector_, sectors_);
  return stack();
}

SkyImages SkyView::prepared(std::size_t min_frames, std::string_view method) const {
  if (keep_.empty() && left_out_.empty()) return source_->sky(min_frames, method);
  return sky_of(source_->frames(min_frames, method), keep_.empty() ? nullptr : &keep_,
                left_out_.empty() ? nullptr : &left_out_, min_frames, method);
}

bool SkyView::within_whole(const SkyImages& prepared) const {
  const SkyImages* whole = source_->sky_if_prepared();
  if (!whole) return false;
  if (keep_.empty()) return true;  // the whole sky, or it without a sector
  // A frame subset's valid pixels include the whole stack's: the same, unless a dropped frame alone
  // could not use some.
  return prepared.valid == whole->valid;
}

SkyMask SkyView::sky_mask(const SkyImages& prepared, const SkyMaskParams& p) const {
  if (prepared.frames() == 0 || !stack().camera) return compute_sky_mask(prepared, stack(), p);
  const SkyImages* whole = source_->sky_if_prepared();
  const bool defaults = p.min_shape == SkyMaskParams{}.min_shape && p.low_ratio == SkyMaskParams{}.low_ratio &&
                        p.aolp_min_deg == SkyMaskParams{}.aolp_min_deg && p.saturated == SkyMaskParams{}.saturated &&
                        p.dark == SkyMaskParams{}.dark;  // what the cached judgments were made with
  if (defaults && left_out_.empty() && within_whole(prepared)) {
    const SkyJudgments& j = source_->judgments();
    if (aolp_and_s0(prepared, frames_) == std::pair(j.have_aolp, j.have_s0))
      return mask_from_judgments(*whole, j, p, keep_.empty() ? nullptr : &keep_);
  }
  const std::vector<const FrameEVectors*> ev = e_vectors(prepared);
  return mask_from_judgments(prepared, judge_sky(prepared, frames_, *stack().camera, p, &ev), p);
}

std::vector<const FrameEVectors*> SkyView::e_vectors(const SkyImages& prepared) const {
  std::vector<const FrameEVectors*> ev(frames_.size(), nullptr);
  if (!within_whole(prepared)) return ev;
  tbb::parallel_for(std::size_t{0}, ev.size(), [&](std::size_t t) { ev[t] = source_->e_vectors(index_[t]); });
  return ev;
}

}  // namespace skypol::skypole
