// Helpers every method leans on, checked against an independent computation: nth_smallest
// (sky_images.h) against std::nth_element on signed data, and the sky memo's sun fits
// (sky_memo.h) against the fits themselves, robust and not, asked of one sky.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "sky/units.h"
#include "skypole/sky_images.h"
#include "skypole/stack_sky.h"
#include "skypole/sun_vector.h"
#include "synthetic_stack.h"

using namespace skypol;

namespace {

double by_nth_element(std::vector<double> v, std::size_t k) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

TEST_CASE("nth_smallest is std::nth_element's answer on signed data of every magnitude",
          "[skypole][nth_smallest]") {
  std::mt19937_64 rng(12345);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> decades(-6.0, 6.0);
  // Large enough for the radix path (4096 elements and more), half of them negative, over twelve
  // decades so that the exponent bits order most of them; some repeats and signed zeros.
  for (const std::size_t n : {5000u, 20000u}) {
    std::vector<double> v(n);
    for (double& x : v) x = normal(rng) * std::pow(10.0, decades(rng));
    for (std::size_t i = 0; i < n / 50; ++i) v[i * 50] = v[i * 50 + 1];
    v[3] = 0.0;
    v[4] = -0.0;
    v[5] = -std::numeric_limits<double>::infinity();
    v[6] = std::numeric_limits<double>::infinity();
    const std::size_t negatives = static_cast<std::size_t>(std::count_if(v.begin(), v.end(), [](double x) { return x < 0; }));
    REQUIRE(negatives > n / 3);
    std::vector<std::size_t> ranks = {0, 1, 2, negatives - 1, negatives, negatives + 1, n / 4, n / 2, n - 2, n - 1};
    std::uniform_int_distribution<std::size_t> any(0, n - 1);
    for (int i = 0; i < 40; ++i) ranks.push_back(any(rng));
    for (const std::size_t k : ranks) {
      INFO("n " << n << ", rank " << k);
      const double got = skypole::nth_smallest(v, k);
      const double want = by_nth_element(v, k);
      CHECK(got == want);  // ±0 compare equal; every other value is itself
    }
  }
  // All negative, where an unreversed key would return the largest magnitude for the smallest rank.
  std::vector<double> neg(6000);
  for (std::size_t i = 0; i < neg.size(); ++i) neg[i] = -1.0 - static_cast<double>((i * 7919) % neg.size());
  CHECK(skypole::nth_smallest(neg, 0) == -6000.0);
  CHECK(skypole::nth_smallest(neg, neg.size() - 1) == -1.0);
  CHECK(skypole::quantile(neg, 0.5) == by_nth_element(neg, (neg.size() - 1) / 2));
}

TEST_CASE("quantile's rank conventions pick the elements their definitions name", "[skypole][quantile]") {
  const std::vector<double> v = {7, 1, 5, 3, 9, 2, 8, 4, 6, 10};  // 1..10, shuffled
  using skypole::QuantileRank;
  CHECK(skypole::quantile(v, 0.5) == 5);                          // ⌊0.5·9⌋ = rank 4
  CHECK(skypole::quantile(v, 0.5, QuantileRank::upper) == 6);     // v[10 / 2]
  CHECK(skypole::quantile(v, 0.5, QuantileRank::nearest) == 5);   // ⌈5⌉ − 1 = rank 4
  CHECK(skypole::quantile(v, 0.95) == 9);                         // ⌊8.55⌋ = rank 8
  CHECK(skypole::quantile(v, 0.95, QuantileRank::nearest) == 10); // ⌈9.5⌉ − 1 = rank 9
  CHECK(skypole::quantile(v, 1.0, QuantileRank::upper) == 10);    // ⌊10⌋ capped at rank 9
  CHECK(skypole::quantile(v, 0.0, QuantileRank::nearest) == 1);   // ⌈0⌉ raised to rank 0
  CHECK(skypole::quantile({}, 0.5, QuantileRank::nearest) == 0);
}

TEST_CASE("the sky memo keeps robust and plain sun fits of one sky apart", "[skypole][sky_memo]") {
  // A sky whose AoLP is turned by 40° inside a disc, in every frame: the robust fit sets those
  // pixels aside, the plain least squares is pulled by them, so the two suns differ.
  stack::Stack stack = testing::make_stack(testing::paper_day(64, 0, 0.0));
  const Eigen::Vector3d centre = Eigen::Vector3d(0.5, 0.3, 0.8).normalized();
  testing::veil_disc(stack, centre, 25, [](std::size_t, const Eigen::Vector3d&, float&, float& aolp) {
    aolp = static_cast<float>(std::remainder(static_cast<double>(aolp) + rad_from_deg(40), std::numbers::pi));
  });
  skypole::InputOptions input;
  input.sky_mask = false;  // the memo's sky keeps the veil
  const skypole::StackSky whole(stack, input);
  const skypole::SkyImages& sky = whole.sky(1, "test");
  const skypole::SkyMemo& memo = whole.memo();
  const skypole::SkyMemo::Entry& entry = memo.on(sky);
  const double min_dolp = skypole::StackSky::kEVectorMinDolp;
  int differing = 0;
  for (std::size_t f = 0; f < stack.frames.size(); ++f) {
    const skypole::FrameEVectors* ev = whole.e_vectors(f);
    REQUIRE(ev != nullptr);
    double q_robust = 0, q_plain = 0;
    const auto robust = skypole::sun_from_aolp(sky, sky.dolp[f], *ev, min_dolp, &q_robust, true);
    const auto plain = skypole::sun_from_aolp(sky, sky.dolp[f], *ev, min_dolp, &q_plain, false);
    // Asked in both orders (odd frames plain first), each answer is its own kind's.
    double q1 = 0, q2 = 0;
    const bool plain_first = f % 2 == 1;
    const auto first = memo.aolp_sun(entry, sky, f, f, *ev, min_dolp, !plain_first, &q1);
    const auto second = memo.aolp_sun(entry, sky, f, f, *ev, min_dolp, plain_first, &q2);
    const auto& memo_robust = plain_first ? second : first;
    const auto& memo_plain = plain_first ? first : second;
    REQUIRE(robust.has_value() == memo_robust.has_value());
    REQUIRE(plain.has_value() == memo_plain.has_value());
    if (!robust || !plain) continue;
    CHECK(*memo_robust == *robust);
    CHECK(*memo_plain == *plain);
    CHECK((plain_first ? q2 : q1) == q_robust);
    CHECK((plain_first ? q1 : q2) == q_plain);
    if (std::acos(std::clamp(robust->dot(*plain), -1.0, 1.0)) > 1e-6) ++differing;
  }
  // The test can fail: the two kinds of fit differ on this sky.
  CHECK(differing >= static_cast<int>(stack.frames.size()) / 2);
}

TEST_CASE("pick_band: the band the estimators read, and so the channels estimate decodes", "[skypole][band]") {
  skypole::InputOptions asked;
  asked.band = "G";
  const skypole::InputOptions none;
  CHECK(skypole::pick_band({"R", "G", "B"}, {}, asked) == "G");  // the asked band wins
  CHECK(skypole::pick_band({"R", "G", "B"}, {}, none) == "B");   // else B
  // Else the first listed band, even where a DoLP.B channel exists without B among the bands.
  CHECK(skypole::pick_band({"R", "G"}, {"DoLP.B", "DoLP.R"}, none) == "R");
  // No bands: the first DoLP channel by name, in any order given; none at all: Y.
  CHECK(skypole::pick_band({}, {"S0.Z", "DoLP.Z", "DoLP.A"}, none) == "A");
  CHECK(skypole::pick_band({}, {"mask"}, none) == "Y");
}
