// sun_vector's model-misfit gate (its registry entry: max_model_misfit 1 %, misfit measured by
// run_method): the gate's threshold on a hand-set misfit, and the whole chain on Berry's sky, whose
// DoLP departs from Rayleigh's law by ~3 % (sun_vector_test), against a Rayleigh sky of ~0.
#include <catch2/catch.hpp>

#include "skypole/evaluate.h"
#include "skypole/method_registry.h"
#include "skypole/sun_vector.h"
#include "synthetic_stack.h"

using namespace skypol;

namespace {

stack::Stack day(const std::string& sky_model) {
  testing::SyntheticSpec spec = testing::paper_day(64, 30, 0.0);
  spec.sky_model = sky_model;
  return testing::make_stack(spec);
}

}  // namespace

TEST_CASE("sun_vector's misfit gate declines past 1 % and only there", "[skypole][gates][misfit]") {
  const skypole::Method& m = skypole::method_entry("sun_vector");
  CHECK(m.traits.misfit_measured);
  REQUIRE(m.calibration.max_model_misfit == 0.01);
  const stack::Stack stack = day("rayleigh");
  // A valid answer that passes every other gate (residual 0, the paper's 8-hour window).
  skypole::PoleEstimate e;
  e.method = "sun_vector";
  e.valid = true;
  e.model_misfit = 0.0099;
  skypole::PoleEstimate below = e;
  skypole::apply_calibration_gates(below, m.calibration, stack, {});
  CHECK(below.valid);
  skypole::PoleEstimate above = e;
  above.model_misfit = 0.0101;
  skypole::apply_calibration_gates(above, m.calibration, stack, {});
  CHECK_FALSE(above.valid);
  CHECK_THAT(above.why_invalid, Catch::StartsWith("the sky is not the model this method fits") &&
                                    Catch::Contains("by 1.0 % of the fitted maximum") && Catch::Contains("the 1.0 %"));
  // Uncalibrated (the calibration study's raw runs): no gate.
  skypole::InputOptions raw;
  raw.calibrated = false;
  skypole::PoleEstimate ungated = above;
  ungated.valid = true;
  skypole::apply_calibration_gates(ungated, m.calibration, stack, raw);
  CHECK(ungated.valid);
}

TEST_CASE("run_method measures sun_vector's misfit, and Berry's sky is declined for it", "[skypole][gates][misfit]") {
  const skypole::PoleEstimate clear = skypole::run_method(day("rayleigh"), "sun_vector");
  INFO(clear.why_invalid);
  REQUIRE(clear.valid);
  CHECK(clear.model_misfit < 0.002);
  const stack::Stack berry = day("berry");
  const double misfit = skypole::rayleigh_law_misfit(berry, {});
  REQUIRE(misfit > 0.015);
  const skypole::PoleEstimate e = skypole::run_method(berry, "sun_vector");
  CHECK_FALSE(e.valid);
  CHECK_THAT(e.why_invalid, Catch::StartsWith("the sky is not the model this method fits"));
  CHECK(e.model_misfit == misfit);  // the whole stack's, as the gate read it
}
