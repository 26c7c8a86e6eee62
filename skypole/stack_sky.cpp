// A stack prepared once for an estimate and its jackknives (stack_sky.h).
#include "skypole/stack_sky.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "skypole/sun_vector.h"
#include "skypole/uncertainty.h"

namespace skypol::skypole {

StackSky::StackSky(const stack::Stack& stack, const InputOptions& input)
    : stack_(stack),
      input_(input),
      e_once_(std::make_unique<std::once_flag[]>(stack.frames.size())),
      e_vectors_(stack.frames.size()),
      memo_(stack.frames.size()) {}

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
        frame_e_vectors(sky, sky.dolp[f], it->second, stack_.camera->transport(), kEVectorMinDolp,
                        polarizer_fit(stack_.frames[f], input_.polarizer_model)));
  });
  return &*e_vectors_[f];
}

const SkyJudgments& StackSky::judgments() const {
  std::call_once(judged_once_, [&] {
    // Isolated: a thread that waits here for its loops must not take up another view's work, which
    // may wait on this same once_flag.
    tbb::this_task_arena::isolate([&] {
      const SkyView view(*this);
      const std::vector<const FrameEVectors*> ev = view.e_vectors(*sky_);
      const FrameRefs frames = all_frames(stack_);
      const auto suns = aolp_and_s0(*sky_, frames).first ? view.aolp_suns(*sky_, ev, kMaskMinDolp, true)
                                                          : std::vector<std::optional<Eigen::Vector3d>>{};
      judgments_.emplace(
          judge_sky(*sky_, frames, *stack_.camera, SkyMaskParams{}, &ev, suns.empty() ? nullptr : &suns));
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

bool SkyView::within_whole(const SkyImages& sky) const {
  const SkyImages* whole = source_->sky_if_prepared();
  if (!whole) return false;
  if (keep_.empty()) return true;  // the whole sky, or it without a sector (or a mask of these)
  // A frame subset's prepared sky includes the whole stack's: the same, unless a dropped frame
  // alone could not use some pixels.
  for (std::size_t i = 0; i < sky.valid.size(); ++i)
    if (sky.valid[i] && !whole->valid[i]) return false;
  return true;
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
  const auto judge = [&] {
    const std::vector<const FrameEVectors*> ev = e_vectors(prepared);
    const auto suns = aolp_and_s0(prepared, frames_).first ? aolp_suns(prepared, ev, kMaskMinDolp, true)
                                                           : std::vector<std::optional<Eigen::Vector3d>>{};
    return mask_from_judgments(
        prepared, judge_sky(prepared, frames_, *stack().camera, p, &ev, suns.empty() ? nullptr : &suns), p);
  };
  // A view whose sky is the whole stack's or less (a sector left out): its mask is kept, for the
  // other methods that run the same view (auto's sun_vector, sun_vector_ephemeris, sun_dolp).
  if (defaults && p.bad_share == SkyMaskParams{}.bad_share && within_whole(prepared))
    return source_->memo().sky_mask(source_->memo().on(prepared), keep_, judge);
  return judge();
}

std::vector<std::vector<float>> SkyView::filtered(const SkyImages& sky, double radius_px) const {
  std::vector<std::vector<float>> out(frames_.size());
  const SkyMemo::Entry* on = within_whole(sky) ? &source_->memo().on(sky) : nullptr;
  tbb::parallel_for(std::size_t{0}, frames_.size(), [&](std::size_t t) {
    out[t] = on ? source_->memo().filtered(*on, sky, t, index_[t], radius_px) : disk_filter(sky.dolp[t], sky, radius_px);
  });
  return out;
}

std::vector<std::optional<Eigen::Vector3d>> SkyView::aolp_suns(const SkyImages& sky,
                                                               const std::vector<const FrameEVectors*>& ev,
                                                               double min_dolp, bool robust,
                                                               std::vector<double>* quality) const {
  std::vector<std::optional<Eigen::Vector3d>> suns(frames_.size());
  std::vector<double> q(frames_.size(), 1.0);
  bool cached = true;
  for (const FrameEVectors* e : ev) cached = cached && e && min_dolp >= e->min_dolp;
  const auto aolp = [&](std::size_t t) -> const std::vector<float>* {
    const auto it = frames_[t]->channels.find("AoLP." + sky.band);
    return it == frames_[t]->channels.end() || it->second.size() != sky.pixels() ? nullptr : &it->second;
  };
  const SkyMemo::Entry* on = cached ? &source_->memo().on(sky) : nullptr;
  tbb::parallel_for(std::size_t{0}, frames_.size(), [&](std::size_t t) {
    if (on)
      suns[t] = source_->memo().aolp_sun(*on, sky, t, index_[t], *ev[t], min_dolp, robust, &q[t]);
    else if (ev[t] && min_dolp >= ev[t]->min_dolp)
      suns[t] = sun_from_aolp(sky, sky.dolp[t], *ev[t], min_dolp, &q[t], robust);
    else if (const std::vector<float>* a = aolp(t))
      suns[t] = sun_from_aolp(sky, sky.dolp[t], *a, *stack().camera, min_dolp,
                              polarizer_fit(*frames_[t], source_->input().polarizer_model), &q[t], robust);
  });
  if (quality) *quality = std::move(q);
  return suns;
}

std::vector<const FrameEVectors*> SkyView::e_vectors(const SkyImages& prepared) const {
  std::vector<const FrameEVectors*> ev(frames_.size(), nullptr);
  if (!within_whole(prepared)) return ev;
  tbb::parallel_for(std::size_t{0}, ev.size(), [&](std::size_t t) { ev[t] = source_->e_vectors(index_[t]); });
  return ev;
}

}  // namespace skypol::skypole
