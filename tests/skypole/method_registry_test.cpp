// The estimators' registry (skypole/method_registry.h): a method registered here, in the test
// binary, with no other edit, is run by run_method, weighed by auto and listed by a study; and
// `--site unknown` (InputOptions::use_site) makes auto site-free.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include "skypole/evaluate.h"
#include "skypole/method_registry.h"
#include "skypole/run_bare.h"
#include "skypole/sky_images.h"
#include "studies/tradeoff_scoring.h"
#include "synthetic_stack.h"

using namespace skypol;

namespace {

// A trivial method that reads no pixel: it answers with the stack's true pole (an oracle), so that
// what run_method and auto make of it is known in advance. Its jackknife sub-runs all give the same
// answer, so its σ is its calibration's floor alone.
constexpr double kOracleFloorDeg = 0.4;

skypole::Method oracle_method() {
  skypole::Method m;
  m.name = "test_oracle";
  m.description = "the true pole (a test's trivial method)";
  m.bare = [](const skypole::SkyView& view) {
    const skypole::SkyImages geometry = skypole::sky_geometry(view.stack(), view.input());
    const Eigen::Vector3d pole = testing::true_pole_camera(view.stack());
    const bool north = view.stack().frames.front().truth.pole_is_north;
    return skypole::make_estimate("test_oracle", geometry, north ? pole : Eigen::Vector3d(-pole), view.input());
  };
  m.traits = {.frame_jackknife_max_groups = 6, .sector_jackknife = false};
  m.calibration = {.method = "", .inflation = 1.0, .floor_deg = kOracleFloorDeg};
  return m;
}

// The one registration line a new method needs (here at static initialisation of the test binary).
const bool registered = skypole::register_method(oracle_method());

// The paper's day, hourly, at 40 pixels: every method answers, in little time.
stack::Stack small_day() {
  testing::SyntheticSpec spec = testing::paper_day(40, 30, 0.0);
  spec.times = testing::times_every("2022-09-23T08:00:00Z", "2022-09-23T16:00:00Z", 60);
  return testing::make_stack(spec);
}

}  // namespace

TEST_CASE("a registered method is listed, dispatched, described", "[skypole][registry]") {
  REQUIRE(registered);
  const auto& names = skypole::method_names();
  // After the built-in ones, before "auto", which stays last.
  REQUIRE(names.size() >= 3);
  CHECK(names.back() == "auto");
  CHECK(names[names.size() - 2] == "test_oracle");
  CHECK(names.front() == "classic");
  CHECK(skypole::method_names_list().find("test_oracle, auto") != std::string::npos);
  CHECK(skypole::methods_json().find("\"name\": \"test_oracle\"") != std::string::npos);
  REQUIRE(skypole::find_method("test_oracle") != nullptr);
  CHECK(skypole::find_method("test_oracle")->calibration.method == "test_oracle");
  CHECK(skypole::find_method("auto") == nullptr);
  CHECK_THROWS_WITH(skypole::register_method(oracle_method()), Catch::Contains("registered already"));
  CHECK_THROWS_WITH(skypole::method_entry("magic"), Catch::Contains("test_oracle") && Catch::Contains("magic"));

  const stack::Stack stack = small_day();
  // run_bare: the answer as it stands; run_method: the same pole, with the jackknife (no scatter) and
  // the calibration's floor as its σ.
  const skypole::PoleEstimate bare = skypole::run_bare(skypole::SkyView(skypole::StackSky(stack, {})), "test_oracle");
  REQUIRE(bare.valid);
  const skypole::PoleEstimate e = skypole::run_method(stack, "test_oracle");
  INFO(e.why_invalid);
  REQUIRE(e.valid);
  CHECK(e.method == "test_oracle");
  CHECK(skypole::score(e, stack.frames.front().truth).angular_error_deg < 1e-6);
  CHECK(e.sigma_deg == Approx(kOracleFloorDeg).epsilon(1e-6));
  CHECK(e.jackknife_frame_groups == 6);
  CHECK(e.jackknife_sectors_rad2.isZero());  // its traits say: no sector jackknife
}

TEST_CASE("auto and a study see a registered method without another edit", "[skypole][registry]") {
  const stack::Stack stack = small_day();
  // auto runs it with the others: the note names it among the answers it weighed.
  const skypole::PoleEstimate a = skypole::run_method(stack, "auto");
  INFO(a.why_invalid << " / " << a.note);
  CHECK(a.note.find("test_oracle") != std::string::npos);
  // combine_estimates weighs it: alone, auto returns its answer.
  const skypole::PoleEstimate oracle = skypole::run_method(stack, "test_oracle");
  const skypole::PoleEstimate alone = skypole::combine_estimates(stack, {}, {oracle});
  REQUIRE(alone.valid);
  CHECK(alone.method == "auto");
  CHECK(alone.sigma_deg == oracle.sigma_deg);
  CHECK_THAT(alone.note, Catch::StartsWith("the answer of test_oracle"));
  // A study's table gets a row for it.
  studies::tradeoff::Table table(studies::tradeoff::with_score_columns({}));
  studies::tradeoff::score_every_method(stack, table, [](studies::tradeoff::Table&) {});
  CHECK(table.size() == skypole::method_names().size());
  CHECK(table.csv().find("\ntest_oracle,1,") != std::string::npos);
}

TEST_CASE("--site unknown: the ephemeris declines, auto is site-free, scoring is unchanged",
          "[skypole][registry][site]") {
  stack::Stack stack = small_day();
  skypole::InputOptions withheld;
  withheld.use_site = false;
  CHECK(skypole::site_usable(stack, {}));
  CHECK_FALSE(skypole::site_usable(stack, withheld));
  CHECK(skypole::parse_site_use("stack"));
  CHECK_FALSE(skypole::parse_site_use("unknown"));
  CHECK_THROWS_WITH(skypole::parse_site_use("Marseille"), Catch::Contains("stack or unknown"));

  CHECK_THROWS_WITH(skypole::run_method(stack, "sun_vector_ephemeris", withheld),
                    Catch::Contains("needs the site") && Catch::Contains("--site unknown"));
  CHECK(skypole::used_by_auto("sun_vector_ephemeris", true));
  CHECK_FALSE(skypole::used_by_auto("sun_vector_ephemeris", false));
  CHECK(skypole::used_by_auto("sun_vector", false));
  CHECK_FALSE(skypole::used_by_auto("auto", true));

  // With the site, auto's answer is the ephemeris'; withheld, auto neither runs nor names it, and
  // answers as it does on a capture whose site is unknown (the same stack, site_known = false).
  std::vector<skypole::PoleEstimate> all;
  for (const skypole::Method& m : skypole::methods()) all.push_back(skypole::run_method(stack, m.name));
  const skypole::PoleEstimate with_site = skypole::combine_estimates(stack, {}, all);
  REQUIRE(with_site.valid);
  CHECK_THAT(with_site.note, Catch::StartsWith("the answer of sun_vector_ephemeris"));
  const skypole::PoleEstimate free = skypole::run_method(stack, "auto", withheld);
  INFO(free.why_invalid << " / " << free.note);
  REQUIRE(free.valid);
  CHECK(free.note.find("sun_vector_ephemeris") == std::string::npos);
  // The same answers combined with the site withheld: the ephemeris left out, the same answer.
  const skypole::PoleEstimate combined = skypole::combine_estimates(stack, withheld, all);
  CHECK(combined.note == free.note);
  CHECK(combined.latitude_deg == free.latitude_deg);
  stack::Stack unknown = stack;
  unknown.site_known = false;
  const skypole::PoleEstimate capture = skypole::run_method(unknown, "auto");
  CHECK(capture.valid);
  CHECK(capture.note == free.note);
  CHECK(capture.heading_deg == free.heading_deg);
  CHECK(capture.latitude_deg == free.latitude_deg);
  CHECK(capture.sigma_deg == free.sigma_deg);
  // The ephemeris on the capture says why it cannot run, differently from a withheld site.
  CHECK_THROWS_WITH(skypole::run_method(unknown, "sun_vector_ephemeris"), Catch::Contains("give [site] when importing"));
}
