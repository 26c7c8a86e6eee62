// Work made once per set of valid pixels (sky_memo.h).
#include "skypole/sky_memo.h"

#include <deque>
#include <map>
#include <utility>

#include <tbb/task_arena.h>

#include "skypole/sun_vector.h"

namespace skypol::skypole {

class SkyMemo::Entry {
 public:
  Entry(std::vector<std::uint8_t> valid_pixels, std::uint64_t key, std::size_t frames)
      : valid(std::move(valid_pixels)), hash(key), frames_(frames) {}
  const std::vector<std::uint8_t> valid;
  const std::uint64_t hash;

  struct Fit {
    std::once_flag once;
    std::optional<Eigen::Vector3d> sun;
    double quality = 1.0;
  };
  Fit& fit(double min_dolp, bool robust, std::size_t f) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (Kind& k : kinds_)
      if (k.min_dolp == min_dolp && k.robust == robust) return k.fits[f];
    kinds_.push_back({min_dolp, robust, std::make_unique<Fit[]>(frames_)});
    return kinds_.back().fits[f];
  }

  struct Mask {
    std::once_flag once;
    SkyMask mask;
  };
  Mask& mask(const std::vector<std::uint8_t>& keep) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (auto& [k, m] : masks_)
      if (k == keep) return *m;
    masks_.emplace_back(keep, std::make_unique<Mask>());
    return *masks_.back().second;
  }

  struct Filtered {
    std::once_flag once;
    std::vector<float> image;
  };
  // The slot of frame f's filter at this radius; a new one (`created`) only when `create`, else nullptr.
  Filtered* filtered(std::size_t f, double radius_px, bool create, bool& created) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    created = false;
    const auto it = filtered_.find({f, radius_px});
    if (it != filtered_.end()) return it->second.get();
    if (!create) return nullptr;
    created = true;
    return filtered_.emplace(std::pair(f, radius_px), std::make_unique<Filtered>()).first->second.get();
  }

 private:
  struct Kind {  // the fits at one min_dolp, robust or not: one per stack frame
    double min_dolp;
    bool robust;
    std::unique_ptr<Fit[]> fits;
  };
  std::size_t frames_;
  mutable std::mutex mutex_;
  mutable std::deque<Kind> kinds_;
  mutable std::vector<std::pair<std::vector<std::uint8_t>, std::unique_ptr<Mask>>> masks_;  // by the frames kept
  mutable std::map<std::pair<std::size_t, double>, std::unique_ptr<Filtered>> filtered_;
};

SkyMemo::SkyMemo(std::size_t frames) : frames_(frames), budget_images_(2 * frames) {}

SkyMemo::~SkyMemo() = default;

const SkyMemo::Entry& SkyMemo::on(const SkyImages& sky) const {
  std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the valid pixels' indices
  for (std::size_t i = 0; i < sky.valid.size(); ++i)
    if (sky.valid[i]) hash = (hash ^ i) * 1099511628211ull;
  const std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& e : entries_)
    if (e->hash == hash && e->valid == sky.valid) return *e;
  entries_.push_back(std::make_unique<Entry>(sky.valid, hash, frames_));
  return *entries_.back();
}

std::optional<Eigen::Vector3d> SkyMemo::aolp_sun(const Entry& on, const SkyImages& sky, std::size_t t,
                                                 std::size_t f, const FrameEVectors& ev, double min_dolp,
                                                 bool robust, double* quality) const {
  Entry::Fit& fit = on.fit(min_dolp, robust, f);
  std::call_once(fit.once, [&] { fit.sun = sun_from_aolp(sky, sky.dolp[t], ev, min_dolp, &fit.quality, robust); });
  if (quality) *quality = fit.quality;
  return fit.sun;
}

SkyMask SkyMemo::sky_mask(const Entry& on, const std::vector<std::uint8_t>& keep,
                          const std::function<SkyMask()>& make) const {
  Entry::Mask& m = on.mask(keep);
  // Isolated: a thread that waits here for make()'s loops must not take up another view's work,
  // which may wait on this same once_flag.
  std::call_once(m.once, [&] { tbb::this_task_arena::isolate([&] { m.mask = make(); }); });
  return m.mask;
}

std::vector<float> SkyMemo::filtered(const Entry& on, const SkyImages& sky, std::size_t t, std::size_t f,
                                     double radius_px) const {
  Entry::Filtered* m = nullptr;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    bool created = false;
    m = on.filtered(f, radius_px, filtered_images_ < budget_images_, created);
    filtered_images_ += created ? 1 : 0;
  }
  if (!m) return disk_filter(sky.dolp[t], sky, radius_px);
  std::call_once(m->once, [&] { m->image = disk_filter(sky.dolp[t], sky, radius_px); });
  return m->image;
}

}  // namespace skypol::skypole
