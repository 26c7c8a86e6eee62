// classic's registry entry (method_registry.h): the paper's algorithm (classic.h).
#include <memory>

#include "skypole/classic.h"
#include "skypole/method_registry.h"

namespace skypol::skypole {

Method classic_method() {
  Method m;
  m.name = "classic";
  m.description = "the paper's SkyPole: where DoLP stays constant between frames (classic.h)";
  m.bare = [](const SkyView& view) {
    // classic reads a stack (its jackknife re-pairs the frames it filtered once: classic.h).
    ClassicParams p;
    p.input = view.input();
    if (view.is_whole()) return estimate_classic(view.stack(), p).estimate;
    return estimate_classic(view.copy(), p).estimate;
  };
  m.run = [](const StackSky& whole, ClassicImages* images) {
    // The frames are filtered once; the frame jackknife re-pairs the frames it keeps.
    auto p = std::make_shared<ClassicParams>();
    p->input = whole.input();
    p->keep_intermediates = images != nullptr;
    auto prepared = std::make_shared<const ClassicPrepared>(
        prepare_classic(whole.sky(classic_min_frames(*p), "classic"), *p));
    ClassicResult r = classic_from(*prepared, *p);
    if (images) *images = std::move(r.images);
    p->keep_intermediates = false;
    MethodRun run;
    run.estimate = r.estimate;
    run.without_frames = [p, prepared](const std::vector<std::uint8_t>& keep) {
      return classic_from(*prepared, *p, &keep).estimate;
    };
    return run;
  };
  // classic stays the paper's: no sector jackknife.
  m.traits = {.frame_jackknife_max_groups = 6, .sector_jackknife = false, .misfit_measured = true};
  // The frame-only calibration: it answers too few random scenes to tune more. Its residual term
  // counts what exceeds its blob's few pixels; its binary images find where DoLP stays constant,
  // which is the pole only for a sky whose DoLP is a function of the angle to the sun, hence the
  // ring-anisotropy and misfit gates.
  m.calibration = {.method = m.name, .inflation = 6.0, .floor_deg = 0.0, .residual_share = 0.25, .residual_pixels = 6.0,
                   .max_ring_anisotropy = 0.2, .max_model_misfit = 0.01, .unpolarized_deg = 2.0};
  return m;
}

}  // namespace skypol::skypole
