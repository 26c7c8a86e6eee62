// A jackknife's sub-run on a view of a stack prepared once (skypole/stack_sky.h) against the same
// run on a copy of the stack (frames_kept, sector_left_out: what the jackknives reran before): the
// prepared sky, the sky mask and every method's answer must be the same to the bit. The stack is
// made to take every path a view has: a veil in two frames only (so that a pixel's mask depends on
// which frames are kept), an S0 channel saturated in one frame, and a patch that only one frame
// masks, as a sensor masks what it clipped (so that the frames without it see more sky).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "sky/units.h"
#include "skypole/evaluate.h"
#include "skypole/run_bare.h"
#include "skypole/sky_images.h"
#include "skypole/sky_mask.h"
#include "skypole/stack_sky.h"
#include "skypole/uncertainty.h"
#include "synthetic_stack.h"

using namespace skypol;

namespace {

stack::Stack awkward_day() {
  testing::SyntheticSpec spec = testing::paper_day(96, 30, 0.01);
  spec.times = testing::times_every("2022-09-23T08:00:00Z", "2022-09-23T14:00:00Z", 60);  // 7 frames
  stack::Stack stack = testing::make_stack(spec);
  const std::size_t n = 96 * 96;
  const Eigen::Vector3d veil(-std::sin(50 * kRadPerDeg) * 0.6, std::sin(50 * kRadPerDeg) * 0.8, std::cos(50 * kRadPerDeg));
  testing::veil_disc(stack, veil, 30, [](std::size_t frame, const Eigen::Vector3d&, float& dolp, float& aolp) {
    if (frame != 2 && frame != 5) return;  // bad in 2 of 7 frames: masked, unless one of them is left out
    dolp *= 0.1f;
    aolp = static_cast<float>(std::remainder(static_cast<double>(aolp) + 40 * kRadPerDeg, std::numbers::pi));
  });
  for (std::size_t k = 0; k < stack.frames.size(); ++k) {
    stack::Frame& f = stack.frames[k];
    std::vector<float>& s0 = f.channels["S0.Y"];  // brightest in a band of columns that moves
    s0.resize(n);
    for (std::size_t i = 0; i < n; ++i) s0[i] = 0.5f + 0.2f * static_cast<float>((i % 96 + 13 * k) % 96) / 96.0f;
    if (k == 3)
      for (std::size_t i = 40 * 96 + 40; i < 40 * 96 + 52; ++i) s0[i] = 2.0f;  // saturated in frame 3
    if (k == 1) {  // frame 1 clipped a patch, and masked it
      std::vector<float>& clipped = f.channels["clipped"];
      clipped.assign(n, 0.0f);
      for (int y = 20; y < 30; ++y)
        for (int x = 50; x < 62; ++x) {
          f.channel("mask")[static_cast<std::size_t>(y * 96 + x)] = 0.0f;
          clipped[static_cast<std::size_t>(y * 96 + x)] = 1.0f;
        }
    }
  }
  return stack;
}

void require_same_sky(const skypole::SkyImages& a, const skypole::SkyImages& b) {
  REQUIRE(a.valid == b.valid);
  REQUIRE(a.valid_count == b.valid_count);
  REQUIRE(a.ray_camera == b.ray_camera);
  REQUIRE(a.clipped_rays == b.clipped_rays);
  REQUIRE(a.dolp == b.dolp);
  REQUIRE(a.times_s == b.times_s);
  REQUIRE(a.times_known == b.times_known);
  REQUIRE(a.band == b.band);
}

void require_same_mask(const skypole::SkyMask& a, const skypole::SkyMask& b) {
  REQUIRE(a.masked == b.masked);
  REQUIRE(a.masked_count == b.masked_count);
  REQUIRE(a.low_dolp == b.low_dolp);
  REQUIRE(a.wrong_aolp == b.wrong_aolp);
  REQUIRE(a.saturated == b.saturated);
  REQUIRE(a.dark == b.dark);
  REQUIRE(a.suns == b.suns);
}

// Every number of an answer but its run time (and the misfit, which a sub-run does not measure).
void require_same_answer(const skypole::PoleEstimate& a, const skypole::PoleEstimate& b) {
  INFO(a.method << ": " << a.why_invalid << " / " << b.why_invalid);
  REQUIRE(a.valid == b.valid);
  REQUIRE(a.why_invalid == b.why_invalid);
  REQUIRE(a.note == b.note);
  REQUIRE(a.pole_camera == b.pole_camera);
  REQUIRE(a.pole_level == b.pole_level);
  REQUIRE(a.pixel == b.pixel);
  REQUIRE(a.is_north == b.is_north);
  REQUIRE(a.heading_deg == b.heading_deg);
  REQUIRE(a.latitude_deg == b.latitude_deg);
  REQUIRE(a.residual_deg == b.residual_deg);
  REQUIRE(a.sun_elevation_misfit_deg == b.sun_elevation_misfit_deg);
}

// What each view must match: its copy, prepared and run from scratch.
void require_view_is_its_copy(const skypole::SkyView& view) {
  const stack::Stack copy = view.copy();
  const skypole::SkyImages sky = view.prepared(1, "test");
  require_same_sky(sky, skypole::prepare_sky_images(copy, {}, 1, "test"));
  require_same_mask(view.sky_mask(sky), skypole::compute_sky_mask(sky, copy));
  const skypole::StackSky alone(copy, view.input());
  for (const char* m : {"sun_vector", "sun_vector_ephemeris", "sun_dolp", "invariance", "great_circle"})
    require_same_answer(skypole::run_bare(view, m), skypole::run_bare(skypole::SkyView(alone), m));
}

}  // namespace

TEST_CASE("a jackknife's view of a stack prepared once answers as its copy does, to the bit",
          "[skypole][uncertainty][stack_sky]") {
  const stack::Stack stack = awkward_day();
  const skypole::StackSky whole(stack, {});
  // The whole stack's work is done first, as run_method does before its jackknives.
  const skypole::SkyImages sky = skypole::SkyView(whole).prepared(1, "test");
  const skypole::SkyMask mask = skypole::SkyView(whole).sky_mask(sky);
  REQUIRE(mask.masked_count > 0);
  REQUIRE(mask.saturated > 0);
  REQUIRE_FALSE(sky.clipped_rays.empty());

  SECTION("without each frame group") {
    const int n = static_cast<int>(stack.frames.size()), k = skypole::frame_jackknife_groups(n);
    int other_sky = 0, other_mask = 0;
    for (int g = 0; g < k; ++g) {
      std::vector<std::uint8_t> keep(static_cast<std::size_t>(n));
      for (int i = 0; i < n; ++i) keep[static_cast<std::size_t>(i)] = i % k != g ? 1 : 0;
      INFO("without frame group " << g);
      const skypole::SkyView view = skypole::SkyView::kept(whole, keep);
      const skypole::SkyImages kept_sky = view.prepared(1, "test");
      other_sky += kept_sky.valid != sky.valid ? 1 : 0;
      other_mask += view.sky_mask(kept_sky).masked != mask.masked ? 1 : 0;
      require_view_is_its_copy(view);
    }
    CHECK(other_sky == 1);   // only without frame 1 does the clipped patch come back
    CHECK(other_mask >= 2);  // without frame 2 or 5 the veil is no longer masked
  }
  SECTION("without each sky sector") {
    const camera::Intrinsics& k = stack.camera->lens().intrinsics();
    for (int g = 0; g < 6; ++g) {
      INFO("without sky sector " << g);
      require_view_is_its_copy(skypole::SkyView::without_sector(whole, Eigen::Vector2d(k.cx, k.cy), g, 6));
    }
  }
  SECTION("a view too small for a method says so as its copy does") {
    std::vector<std::uint8_t> keep(stack.frames.size(), 0);
    keep[0] = keep[4] = 1;
    const skypole::SkyView view = skypole::SkyView::kept(whole, keep);
    const stack::Stack copy = view.copy();
    const skypole::StackSky alone(copy, {});
    for (const char* m : {"sun_vector", "invariance", "great_circle"}) {
      std::string cached, plain;
      try {
        (void)skypole::run_bare(view, m);
      } catch (const std::invalid_argument& e) {
        cached = e.what();
      }
      try {
        (void)skypole::run_bare(skypole::SkyView(alone), m);
      } catch (const std::invalid_argument& e) {
        plain = e.what();
      }
      CHECK_FALSE(cached.empty());
      CHECK(cached == plain);
    }
  }
}

// The jackknives' sub-runs run in parallel (uncertainty.cpp group_jackknife); an answer must not
// depend on how many threads ran them.
TEST_CASE("an answer and its uncertainty are the same on one thread as on many", "[skypole][uncertainty][stack_sky]") {
  const stack::Stack stack = awkward_day();
  skypole::InputOptions input;
  input.calibrated = false;  // the raw jackknives: the most digits to differ in
  std::vector<skypole::PoleEstimate> many, one;
  for (const std::string& m : skypole::method_names()) many.push_back(skypole::run_method(stack, m, input));
  {
    const tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    for (const std::string& m : skypole::method_names()) one.push_back(skypole::run_method(stack, m, input));
  }
  int valid = 0;
  for (std::size_t i = 0; i < many.size(); ++i) {
    require_same_answer(many[i], one[i]);
    REQUIRE(many[i].jackknife_frames_rad2 == one[i].jackknife_frames_rad2);
    REQUIRE(many[i].jackknife_sectors_rad2 == one[i].jackknife_sectors_rad2);
    REQUIRE(many[i].sigma_bearing_deg == one[i].sigma_bearing_deg);
    REQUIRE(many[i].sigma_latitude_deg == one[i].sigma_latitude_deg);
    REQUIRE(many[i].cone95_deg == one[i].cone95_deg);
    REQUIRE(many[i].model_misfit == one[i].model_misfit);
    valid += many[i].valid ? 1 : 0;
  }
  CHECK(valid >= 4);
}

// The prepared skies of a stack and of its views hold no copy of the frames: each frame's DoLP is
// the stack's own channel (sky_images.h FrameImages), so the memory an estimate and its
// jackknives keep does not grow with the number of views. A copy would pass every value check
// above and fail here.
TEST_CASE("prepared skies and their views borrow the stack's DoLP, they do not copy it", "[skypole][stack_sky]") {
  const stack::Stack stack = awkward_day();
  const skypole::StackSky whole(stack, {});
  const skypole::SkyImages& sky = whole.sky(3, "test");
  std::vector<std::uint8_t> keep(stack.frames.size(), 1);
  keep[2] = 0;
  const skypole::SkyImages kept = skypole::SkyView::kept(whole, keep).prepared(3, "test");
  const skypole::SkyImages sector =
      skypole::SkyView::without_sector(whole, Eigen::Vector2d(48, 48), 1, 6).prepared(3, "test");
  const skypole::SkyImages alone = skypole::prepare_sky_images(stack, {}, 3, "test");
  REQUIRE(sky.frames() == stack.frames.size());
  REQUIRE(kept.frames() == stack.frames.size() - 1);
  for (std::size_t k = 0; k < stack.frames.size(); ++k) {
    const std::vector<float>* channel = &stack.frames[k].channel("DoLP.Y");
    CHECK(&sky.dolp[k] == channel);
    CHECK(&sector.dolp[k] == channel);
    CHECK(&alone.dolp[k] == channel);
    if (k != 2) CHECK(&kept.dolp[k < 2 ? k : k - 1] == channel);
  }
}
