// invariance's registry entry (method_registry.h): DoLP's variance over time (invariance.h).
#include <memory>

#include "skypole/invariance.h"
#include "skypole/method_registry.h"

namespace skypol::skypole {

Method invariance_method() {
  Method m;
  m.name = "invariance";
  m.description = "the minimum over the sphere of DoLP's variance over time, then a sub-pixel model (invariance.h)";
  m.bare = [](const SkyView& view) {
    InvarianceParams p;
    p.input = view.input();
    return estimate_invariance(view, p).estimate;
  };
  m.run = [](const StackSky& whole, ClassicImages*) {
    // Its sector jackknife refits its co-rotating window about the pole without each sector of that
    // window (a masked wedge of the whole sky would trip its edge checks).
    InvarianceParams p;
    p.input = whole.input();
    p.sectors = kSkySectors;
    InvarianceResult r = estimate_invariance(SkyView(whole), p);
    MethodRun run;
    run.estimate = r.estimate;
    auto without = std::make_shared<const std::vector<PoleEstimate>>(std::move(r.without_sector));
    run.sectors = !without->empty();  // the per-frame refinement (frames without times) has none
    run.without_sector = [without](int g) { return (*without)[static_cast<std::size_t>(g)]; };
    return run;
  };
  m.traits = {.frame_jackknife_max_groups = 6, .sector_jackknife = true, .misfit_measured = true};
  // Its floor is its numerical error on a noise-free stack. Its co-rotating model takes the sky's
  // pattern to be fixed to the sun, which a sky that also darkens and depolarizes towards the
  // horizon is not (80° per unit of misfit); its σ has no term for the sky a sensor clipped, so a
  // sky more than 30 % clipped has no answer it can state.
  m.calibration = {.method = m.name, .inflation = 0.5, .floor_deg = 0.001, .max_residual_deg = 0.5, .max_clipped_share = 0.3,
                   .sector_inflation = 0.5, .misfit_deg = 80.0};
  return m;
}

}  // namespace skypol::skypole
