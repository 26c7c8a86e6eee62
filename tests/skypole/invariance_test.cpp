// The per-direction time-invariance estimator on synthetic Rayleigh stacks.
#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>

#include "skypole/invariance.h"
#include "synthetic_stack.h"

using namespace skypol;

namespace {

testing::SyntheticSpec paper_spec(double heading) {
  testing::SyntheticSpec spec;
  spec.times = testing::paper_times();
  spec.heading_deg = heading;
  return spec;
}

skypole::Score run(const render::Stack& stack, const skypole::InvarianceParams& p,
                   const std::string& label, skypole::InvarianceResult* out = nullptr) {
  const skypole::InvarianceResult r = skypole::estimate_invariance(stack, p);
  INFO(label << ": " << r.estimate.why_invalid);
  REQUIRE(r.estimate.valid);
  const skypole::Score s = skypole::score(r.estimate, stack.frames.front().truth);
  std::cout << "invariance " << label << ": bearing err "
            << (s.bearing_error_deg ? *s.bearing_error_deg : std::nan("")) << "°, latitude err "
            << s.latitude_error_deg << "°, angular err " << s.angular_error_deg << "°, residual "
            << r.estimate.residual_deg << "°, confidence " << r.estimate.confidence
            << ", detrended " << r.detrended << ", " << r.estimate.seconds << " s\n";
  if (out) *out = r;
  return s;
}

}  // namespace

TEST_CASE("time invariance finds the NCP over Marseille within 0.05 degrees", "[skypole][invariance]") {
  for (double heading : {0.0, 37.0, 200.0}) {
    const render::Stack stack = testing::make_stack(paper_spec(heading));
    const skypole::Score s = run(stack, {}, "Marseille heading " + std::to_string(heading));
    REQUIRE(s.bearing_error_deg);
    CHECK(std::abs(*s.bearing_error_deg) < 0.05);
    CHECK(std::abs(s.latitude_error_deg) < 0.05);
    CHECK(s.angular_error_deg < 0.05);
  }
}

TEST_CASE("time invariance needs the drift removed near the equinox", "[skypole][invariance]") {
  // Without the linear trend the DoLP at the pole itself varies with δ and the minimum moves.
  const render::Stack stack = testing::make_stack(paper_spec(37));
  skypole::InvarianceParams none;
  none.detrend = skypole::Detrend::none;
  const skypole::Score s = run(stack, none, "no detrend");
  CHECK(s.angular_error_deg < 0.5);
}

TEST_CASE("time invariance in the southern hemisphere finds the SCP", "[skypole][invariance]") {
  testing::SyntheticSpec spec;
  spec.latitude_deg = -33.87;
  spec.longitude_deg = 151.21;
  spec.times = testing::times_every("2022-09-22T22:00:00Z", "2022-09-23T06:00:00Z", 30);
  spec.heading_deg = 75;
  const render::Stack stack = testing::make_stack(spec);
  skypole::InvarianceResult r;
  const skypole::Score s = run(stack, {}, "Sydney", &r);
  CHECK_FALSE(r.estimate.is_north);
  CHECK(s.angular_error_deg < 0.1);
}

TEST_CASE("time invariance with sensor noise over the paper's day", "[skypole][invariance]") {
  testing::SyntheticSpec spec = paper_spec(30);
  spec.noise = 0.01;
  spec.max_dolp = 0.7;
  const render::Stack stack = testing::make_stack(spec);
  // Near the equinox the pole lies on every frame's maximum-DoLP circle: DoLP there is stationary
  // in space as well as time, V grows as |u|⁴, and noise moves its minimum by degrees (measured
  // 3.2° for this seed). This documents the weakness; great_circle handles the same stack.
  const skypole::Score s = run(stack, {}, "noise 1 %, Pmax 0.7");
  CHECK(s.angular_error_deg < 6.0);
}

TEST_CASE("time invariance refuses a pole outside the field of view", "[skypole][invariance]") {
  testing::SyntheticSpec spec = paper_spec(180);
  spec.tilt_deg = 90;
  spec.size = 128;
  const render::Stack stack = testing::make_stack(spec);
  const skypole::PoleEstimate e = skypole::estimate_invariance(stack).estimate;
  CHECK_FALSE(e.valid);
  CHECK(e.why_invalid.find("field of view") != std::string::npos);
}

