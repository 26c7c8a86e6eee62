// auto's ranking (skypole/auto.h combine_estimates) on hand-made answers whose outcome is worked
// out by hand: two answers agree when their angle is at most 1.5185 × the root-sum-square of their
// 95 % cones; the centre is the answer most others agree with (ties: the narrowest cone); auto
// declines when the group is no larger than the dissent; it returns the ephemeris' answer as it
// stands when it is in the group, else the inverse-variance mean with the sharpest member's σ.
// Every pole here lies on the meridian of azimuth 10° of a level camera, so that the angles between
// them are differences of altitude, and the tangent-plane offsets (a log map) are those differences.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "skypole/evaluate.h"
#include "fixtures.h"

using namespace skypol;

namespace {

skypole::PoleEstimate answer(const std::string& method, double altitude_deg, double sigma_deg, double cone_deg,
                             double seconds) {
  skypole::PoleEstimate e = testing::pole_at(10, altitude_deg);
  e.method = method;
  e.latitude_deg = altitude_deg;
  e.sigma_deg = sigma_deg;
  e.cone95_deg = cone_deg;
  e.seconds = seconds;
  return e;
}

skypole::PoleEstimate declined(const std::string& method, double seconds) {
  skypole::PoleEstimate e;
  e.method = method;
  e.why_invalid = "test reason";
  e.seconds = seconds;
  return e;
}

// A level camera: its level frame is the one the poles above are given in.
const stack::Stack& level_stack() {
  static const stack::Stack s = testing::make_stack(testing::paper_day(32, 0, 0.0));
  return s;
}

}  // namespace

TEST_CASE("auto: the mean of the group about the centre, outvoted and declined answers named",
          "[skypole][auto]") {
  // great_circle at 40° and sun_vector at 40.5° agree (0.5° ≤ 1.5185·√2 = 2.15°); invariance at 45°,
  // the narrowest cone, agrees with neither (4.5° and 5° > 1.5185·√(1 + 0.25) = 1.70°). Counts (self
  // included): 2, 2, 1, so great_circle, the first of the two, is the centre; the group (2) outnumbers
  // the dissent (1). Its mean about the sharpest (great_circle, σ 0.4°): weights 1/0.16 = 6.25 and
  // 1/0.25 = 4, so 40° + 0.5°·4/10.25 = 40.195122°; σ and cone are great_circle's.
  const std::vector<skypole::PoleEstimate> all = {
      answer("great_circle", 40.0, 0.4, 1.0, 1), answer("sun_vector", 40.5, 0.5, 1.0, 2),
      answer("invariance", 45.0, 0.2, 0.5, 3), declined("sun_dolp", 4)};
  const skypole::PoleEstimate a = skypole::combine_estimates(level_stack(), {}, all);
  INFO(a.why_invalid);
  REQUIRE(a.valid);
  CHECK(a.method == "auto");
  CHECK(a.altitude_deg == Approx(40.0 + 0.5 * 4.0 / 10.25).margin(1e-9));
  CHECK(a.latitude_deg == Approx(40.0 + 0.5 * 4.0 / 10.25).margin(1e-9));
  CHECK(a.azimuth_rel_deg == Approx(10.0).margin(1e-9));
  CHECK(a.sigma_deg == 0.4);
  CHECK(a.cone95_deg == 1.0);
  CHECK(a.seconds == 10);  // every answer auto weighed, declined ones included
  CHECK(a.note ==
        "the inverse-variance mean of the agreeing answers, with the σ of the sharpest, great_circle "
        "(agreeing: sun_vector); outvoted: invariance; declined: sun_dolp: test reason");

  SECTION("the ephemeris in the group: its answer as it stands") {
    // sun_vector_ephemeris at 40.3° agrees with both (0.3° and 0.2° ≤ 1.5185·√(1 + 0.0009) = 1.52°)
    // but not with invariance (4.7°); counts 3, 3, 1, 3: a tie of three, won by its cone of 0.03°.
    std::vector<skypole::PoleEstimate> with = all;
    with.push_back(answer("sun_vector_ephemeris", 40.3, 0.01, 0.03, 5));
    const skypole::PoleEstimate e = skypole::combine_estimates(level_stack(), {}, with);
    REQUIRE(e.valid);
    CHECK(e.altitude_deg == 40.3);
    CHECK(e.sigma_deg == 0.01);
    CHECK(e.seconds == 15);
    CHECK(e.note ==
          "the answer of sun_vector_ephemeris (agreeing: great_circle, sun_vector); outvoted: invariance; "
          "declined: sun_dolp: test reason");
    // The site withheld (--site unknown): the ephemeris is not weighed, and the answer is the mean above.
    skypole::InputOptions withheld;
    withheld.use_site = false;
    const skypole::PoleEstimate f = skypole::combine_estimates(level_stack(), withheld, with);
    REQUIRE(f.valid);
    CHECK(f.altitude_deg == Approx(a.altitude_deg).margin(1e-12));
    CHECK(f.note == a.note);
    CHECK(f.seconds == 10);
  }
}

TEST_CASE("auto: the centre is the answer most others agree with, not the first or the sharpest",
          "[skypole][auto]") {
  // Three answers 1.5° apart in a row, cones 1°: neighbours agree (1.5° ≤ 2.15°), the two ends do not
  // (3°). The middle one, agreed with by all three, is the centre, so that the group is all of them:
  // weights 1/0.09, 1/0.36, 1/0.36 about the sharpest (40°): 40° + (1.5° + 3°)·(1/0.36)/(1/0.09 + 2/0.36)
  // = 40.75°. (Centred on the first or the sharpest, the group would be two and the third outvoted.)
  const std::vector<skypole::PoleEstimate> all = {answer("great_circle", 40.0, 0.3, 1.0, 0),
                                                  answer("sun_vector", 41.5, 0.6, 1.0, 0),
                                                  answer("invariance", 43.0, 0.6, 1.0, 0)};
  const skypole::PoleEstimate a = skypole::combine_estimates(level_stack(), {}, all);
  REQUIRE(a.valid);
  CHECK(a.altitude_deg == Approx(40.75).margin(1e-9));
  CHECK(a.sigma_deg == 0.3);
  CHECK(a.note ==
        "the inverse-variance mean of the agreeing answers, with the σ of the sharpest, great_circle "
        "(agreeing: sun_vector, invariance)");
}

TEST_CASE("auto: of centres agreed with by as many, the narrowest cone's", "[skypole][auto]") {
  // Cones of 1° at 40° and 42.5°, of 0.01° at 41.2° and 41.3°. Each wide one agrees with both narrow
  // ones (1.2°, 1.3° ≤ 1.5185·√(1 + 0.0001) = 1.5186°); the wide ones disagree (2.5° > 2.1475°), and
  // so do the narrow ones (0.1° > 0.0215°): every answer is agreed with by three. The centre is the
  // narrowest, the first of the two narrow ones (41.2°), whose group is both wide ones and itself;
  // the other narrow one is outvoted. The mean about it (σ 0.004°, weight 62 500; the wide ones σ
  // 0.4°, weight 6.25): 41.2° + 6.25·(1.3° − 1.2°)/62 512.5. (Centred on the first answer instead,
  // the group would hold both narrow ones and its mean be near 41.25°.)
  const std::vector<skypole::PoleEstimate> all = {
      answer("great_circle", 40.0, 0.4, 1.0, 0), answer("sun_vector", 41.2, 0.004, 0.01, 0),
      answer("sun_dolp", 41.3, 0.004, 0.01, 0), answer("invariance", 42.5, 0.4, 1.0, 0)};
  const skypole::PoleEstimate a = skypole::combine_estimates(level_stack(), {}, all);
  REQUIRE(a.valid);
  CHECK(a.altitude_deg == Approx(41.2 + 6.25 * (1.3 - 1.2) / (6.25 + 62500 + 6.25)).margin(1e-9));
  CHECK(a.sigma_deg == 0.004);
  CHECK(a.note ==
        "the inverse-variance mean of the agreeing answers, with the σ of the sharpest, sun_vector "
        "(agreeing: great_circle, invariance); outvoted: sun_dolp");
}

TEST_CASE("auto: a group no larger than its dissent declines; a lone answer stands", "[skypole][auto]") {
  // Two answers 5° apart with cones of 0.5° (> 1.5185·√0.5 = 1.07°): one against one, the data do not
  // decide.
  const std::vector<skypole::PoleEstimate> two = {answer("great_circle", 40.0, 0.2, 0.5, 0),
                                                  answer("invariance", 45.0, 0.2, 0.5, 0)};
  const skypole::PoleEstimate d = skypole::combine_estimates(level_stack(), {}, two);
  CHECK_FALSE(d.valid);
  CHECK(d.why_invalid == "the methods disagree beyond their 95 % cones: invariance 5.0° from great_circle "
                         "(cones 0.5°, 0.5°)");
  // One answer alone is its own group.
  const skypole::PoleEstimate one = skypole::combine_estimates(level_stack(), {}, {two[1]});
  REQUIRE(one.valid);
  CHECK(one.altitude_deg == 45.0);
  CHECK(one.note == "the answer of invariance");
  // Answers of what auto does not weigh (itself, an unknown name) are left out.
  const skypole::PoleEstimate none = skypole::combine_estimates(
      level_stack(), {}, {answer("auto", 40.0, 0.2, 0.5, 0), answer("magic", 40.0, 0.2, 0.5, 0)});
  CHECK_FALSE(none.valid);
  CHECK(none.why_invalid == "no method could answer ()");
}
