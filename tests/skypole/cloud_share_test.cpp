// The cloud gate's measure (skypole/cloud_share.h) and the gate itself (run_method): a clear day
// scores ≈ 0, a sky with an unpolarized half scores that half, and a method whose calibration has
// a cloud threshold declines such a sky, naming cloud.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "skypole/cloud_share.h"
#include "skypole/evaluate.h"
#include "skypole/sky_images.h"
#include "fixtures.h"

using namespace skypol;

namespace {

// Thick cloud over the half of the image with camera x > 0, in every frame: the DoLP there drops
// to a tenth (sky/clouds.h: a thick cloud is unpolarized); the AoLP stays.
stack::Stack with_cloud(stack::Stack stack, double& covered_share) {
  const skypole::SkyImages sky = skypole::prepare_sky_images(stack, {}, 1, "test");
  std::size_t covered = 0;
  for (std::size_t i = 0; i < sky.pixels(); ++i) covered += sky.valid[i] && sky.ray_camera[i].x() > 0 ? 1 : 0;
  covered_share = static_cast<double>(covered) / static_cast<double>(sky.valid_count);
  for (stack::Frame& f : stack.frames) {
    std::vector<float>& dolp = f.channel("DoLP." + sky.band);
    for (std::size_t i = 0; i < sky.pixels(); ++i)
      if (sky.valid[i] && sky.ray_camera[i].x() > 0) dolp[i] *= 0.1f;
  }
  return stack;
}

// The paper's clear day, 128 px.
stack::Stack clear_day() {
  testing::SyntheticSpec spec = testing::paper_spec(30);
  spec.size = 128;
  return testing::make_stack(spec);
}

}  // namespace

TEST_CASE("the unpolarized share: clear day ≈ 0, a half-clouded sky ≈ ½, and the gate declines it",
          "[skypole][cloud]") {
  const stack::Stack clear = clear_day();
  const double clear_share = skypole::unreadable_sky(skypole::prepare_sky_images(clear, {}, 1, "test")).unpolarized;
  INFO("clear " << clear_share);
  CHECK(clear_share < 0.02);

  double covered = 0;
  const stack::Stack cloudy = with_cloud(clear, covered);
  REQUIRE(covered == Approx(0.5).margin(0.05));
  // Pixels near the sun and antisun are left out of the count, so the share of the rest that is
  // covered is not exactly `covered`; within 0.1 of it.
  const double share = skypole::unreadable_sky(skypole::prepare_sky_images(cloudy, {}, 1, "test")).unpolarized;
  INFO("cloudy " << share << " covered " << covered);
  CHECK(share == Approx(covered).margin(0.1));

  // The gate itself (apply_calibration_gates), with a threshold of 0.25: every method that still
  // finds a pole in the cloudy stack with its gates off is declined for the cloud, naming the share;
  // the clear stack's answers are not.
  skypole::InputOptions ungated;
  ungated.calibrated = false;
  ungated.max_uncertainty_deg = std::numeric_limits<double>::infinity();
  int gated = 0;
  for (const char* m : {"great_circle", "invariance", "sun_vector", "sun_vector_ephemeris"}) {
    INFO(m);
    const skypole::MethodCalibration c{.method = m, .max_unpolarized_share = 0.25};
    skypole::PoleEstimate ok = skypole::run_method(clear, m, ungated);
    INFO(ok.why_invalid);
    REQUIRE(ok.valid);
    skypole::apply_calibration_gates(ok, c, clear, {});
    CHECK(ok.valid);
    skypole::PoleEstimate e = skypole::run_method(cloudy, m, ungated);
    if (!e.valid) continue;
    ++gated;
    skypole::apply_calibration_gates(e, c, cloudy, {});
    CHECK_FALSE(e.valid);
    CHECK_THAT(e.why_invalid, Catch::StartsWith("cloud or neutral points: 54 % of the sky") && Catch::Contains("unpolarized"));
  }
  CHECK(gated >= 3);  // great_circle, invariance, sun_vector, sun_vector_ephemeris answer it ungated
}

// A sensor masks the sky it clipped and marks it in channel "clipped" (render/sensor_stage.h). The
// gate counts that sky as unpolarized: a cloud bright enough to clip is still a cloud. The same
// pixels masked without the mark are sky the camera did not see, and count for nothing.
TEST_CASE("the unpolarized share counts the sky a sensor masked for clipping, not the sky it never saw",
          "[skypole][cloud]") {
  const stack::Stack clear = clear_day();
  double covered = 0;
  with_cloud(clear, covered);  // only for the share of the sky at camera x > 0
  const skypole::SkyImages sky = skypole::prepare_sky_images(clear, {}, 1, "test");
  stack::Stack clipped = clear, unseen = clear;
  for (std::size_t k = 0; k < clear.frames.size(); ++k) {
    std::vector<float>& cm = clipped.frames[k].channel("mask");
    std::vector<float>& um = unseen.frames[k].channel("mask");
    std::vector<float>& mark = clipped.frames[k].channels["clipped"];
    mark.assign(sky.pixels(), 0.0f);
    for (std::size_t i = 0; i < sky.pixels(); ++i)
      if (sky.valid[i] && sky.ray_camera[i].x() > 0) {
        cm[i] = um[i] = 0.0f;
        mark[i] = 1.0f;
      }
  }
  const skypole::SkyImages c = skypole::prepare_sky_images(clipped, {}, 1, "test");
  const skypole::SkyImages u = skypole::prepare_sky_images(unseen, {}, 1, "test");
  CHECK(c.valid_count == u.valid_count);  // no method reads the clipped sky
  CHECK(c.valid_count < sky.valid_count * 6 / 10);
  CHECK(u.clipped_rays.empty());
  CHECK(c.clipped_rays.size() == static_cast<std::size_t>(sky.valid_count - c.valid_count));
  INFO("covered " << covered);
  const skypole::UnreadableSky read_c = skypole::unreadable_sky(c), read_u = skypole::unreadable_sky(u);
  CHECK(read_c.unpolarized == Approx(covered).margin(0.1));
  CHECK(read_u.unpolarized < 0.02);
  CHECK(read_c.clipped == Approx(read_c.unpolarized).margin(0.02));  // the clear half reads polarized
  CHECK(read_u.clipped == 0);
  // A sky clipped all over is declined for that, not for want of sky.
  stack::Stack all_clipped = clipped;
  for (stack::Frame& f : all_clipped.frames)
    for (std::size_t i = 0; i < sky.pixels(); ++i)
      if (sky.valid[i]) {
        f.channel("mask")[i] = 0.0f;
        f.channel("clipped")[i] = 1.0f;
      }
  CHECK_THROWS_WITH(skypole::prepare_sky_images(all_clipped, {}, 1, "test"),
                    Catch::StartsWith("test: the sensor clipped the sky") && Catch::Contains("a shorter exposure"));
  // Each method declines it in its own name (sun_dolp and the ephemeris share sun_vector's code).
  for (const char* m : {"sun_vector", "sun_vector_ephemeris", "sun_dolp", "great_circle"})
    CHECK_THROWS_WITH(skypole::run_method(all_clipped, m), Catch::StartsWith(std::string(m) + ": the sensor clipped the sky"));
  // The gate names the clipping, how much of the sky it took, and the cure.
  skypole::InputOptions ungated;
  ungated.calibrated = false;
  ungated.max_uncertainty_deg = std::numeric_limits<double>::infinity();
  skypole::PoleEstimate e = skypole::run_method(clipped, "sun_vector", ungated);
  REQUIRE(e.valid);
  skypole::apply_calibration_gates(e, {.method = "sun_vector", .max_unpolarized_share = 0.25}, clipped, {});
  CHECK_FALSE(e.valid);
  CHECK_THAT(e.why_invalid, Catch::StartsWith("cloud, neutral points or clipping: ") &&
                                Catch::Contains("clipped by the sensor in some frame, which no method reads") &&
                                Catch::Contains("a shorter exposure"));
  // The clipped-share gate (max_clipped_share: invariance's) names the clipping alone; above the
  // half clipped here it lets the answer through.
  skypole::PoleEstimate gated = skypole::run_method(clipped, "sun_vector", ungated);
  skypole::apply_calibration_gates(gated, {.method = "sun_vector", .max_clipped_share = 0.75}, clipped, {});
  CHECK(gated.valid);
  skypole::apply_calibration_gates(gated, {.method = "sun_vector", .max_clipped_share = 0.25}, clipped, {});
  CHECK_FALSE(gated.valid);
  CHECK_THAT(gated.why_invalid, Catch::StartsWith("the sensor clipped the sky: ") && Catch::Contains("a lower gain"));
}

TEST_CASE("ring anisotropy: a Rayleigh sky is a function of the angle to the sun, Berry's neutral points are not",
          "[skypole][cloud][berry]") {
  testing::SyntheticSpec spec = testing::paper_day(128, 30);
  const double rayleigh = skypole::ring_anisotropy(skypole::prepare_sky_images(testing::make_stack(spec), {}, 1, "test"));
  spec.sky_model = "berry";
  const double berry = skypole::ring_anisotropy(skypole::prepare_sky_images(testing::make_stack(spec), {}, 1, "test"));
  INFO("rayleigh " << rayleigh << ", berry " << berry);
  // Rayleigh: only the pixel grid and the found sun's offset from the true one spread the ring.
  CHECK(rayleigh < 0.05);
  // Berry: the lowest DoLP is a neutral point 20° from the sun; on the ring 15–35° around it lie
  // the sun's side (DoLP ≈ 0.05–0.15 of the range) and the far side (up to ≈ 0.3).
  CHECK(berry > 3 * rayleigh);
  CHECK(berry > 0.1);

  // The gate on it, with a threshold between the two: an answer on the Berry sky is declined,
  // naming the shape; one on the Rayleigh sky is not.
  const stack::Stack berry_stack = testing::make_stack(spec);
  spec.sky_model = "rayleigh";
  const stack::Stack rayleigh_stack = testing::make_stack(spec);
  skypole::InputOptions ungated;
  ungated.calibrated = false;
  ungated.max_uncertainty_deg = std::numeric_limits<double>::infinity();
  const skypole::MethodCalibration c{.method = "sun_vector_ephemeris", .max_ring_anisotropy = 0.5 * (rayleigh + berry)};
  skypole::PoleEstimate b = skypole::run_method(berry_stack, c.method, ungated);
  skypole::PoleEstimate r = skypole::run_method(rayleigh_stack, c.method, ungated);
  REQUIRE(b.valid);
  REQUIRE(r.valid);
  skypole::apply_calibration_gates(b, c, berry_stack, {});
  skypole::apply_calibration_gates(r, c, rayleigh_stack, {});
  CHECK_FALSE(b.valid);
  CHECK_THAT(b.why_invalid, Catch::Contains("not the single-scattering shape"));
  CHECK(r.valid);
}
