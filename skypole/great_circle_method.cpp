// great_circle's registry entry (method_registry.h): circles of equal DoLP (great_circle.h).
#include <memory>

#include "skypole/great_circle.h"
#include "skypole/method_registry.h"

namespace skypol::skypole {

Method great_circle_method() {
  Method m;
  m.name = "great_circle";
  m.description = "circles of equal DoLP fitted in 3-D; the pole is their common point (great_circle.h)";
  m.bare = [](const SkyView& view) {
    GreatCircleParams p;
    p.input = view.input();
    return great_circle_pole(great_circle_pairs(view, p), p).estimate;
  };
  m.run = [](const StackSky& whole, ClassicImages*) {
    // The circles are computed once; both jackknives refit only the pole from them (the sector
    // jackknife from the crossings kept outside each sector).
    auto p = std::make_shared<GreatCircleParams>();
    p->input = whole.input();
    p->sectors = kSkySectors;
    auto pairs = std::make_shared<const GreatCirclePairs>(great_circle_pairs(SkyView(whole), *p));
    MethodRun run;
    run.estimate = great_circle_pole(*pairs, *p).estimate;
    run.without_frames = [p, pairs](const std::vector<std::uint8_t>& keep) {
      return great_circle_pole(*pairs, *p, &keep).estimate;
    };
    run.without_sector = [p, pairs](int g) { return great_circle_pole_without_sector(*pairs, *p, g).estimate; };
    return run;
  };
  // Its refits are cheap, so its frame jackknife deletes one frame at a time (up to 24 groups),
  // whose σ is not a few-group draw with a heavy tail.
  m.traits = {.frame_jackknife_max_groups = 24, .sector_jackknife = true, .misfit_measured = true};
  // Its great circles need DoLP to be a function of the angle to the sun alone, which a sky far
  // from Rayleigh's law is not (misfit gate); the sector factor grows with the unpolarized share,
  // since under cloud the sectors measure a bias.
  m.calibration = {.method = m.name, .inflation = 0.45, .floor_deg = 0.05, .max_residual_deg = 5.0, .max_model_misfit = 0.01,
                   .sector_inflation = 0.2, .sector_unpolarized = 1.0};
  return m;
}

}  // namespace skypol::skypole
