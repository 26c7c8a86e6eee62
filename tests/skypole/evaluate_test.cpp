// Dataset-level evaluation: statistics, CSV, dispatch by name, and the measured accuracy table.
#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>

#include "skypole/evaluate.h"
#include "skypole/sky_images.h"
#include "synthetic_stack.h"

using namespace skypol;

TEST_CASE("summary statistics follow their documented definitions", "[skypole][evaluate]") {
  const skypole::Stats s = skypole::summarize_values({4, 1, 3, 2});
  CHECK(s.n == 4);
  CHECK(s.mean == Approx(2.5));
  CHECK(s.median == Approx(2.5));
  CHECK(s.p95 == Approx(4));  // nearest rank: ⌈3.8⌉ = 4th smallest
  CHECK(s.max == Approx(4));
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);
  CHECK(skypole::summarize_values(v).p95 == Approx(95));
  CHECK(skypole::summarize_values({}).n == 0);
}

TEST_CASE("unknown estimators are named with the legal ones", "[skypole][evaluate]") {
  render::Stack stack;
  CHECK_THROWS_WITH(skypole::run_method(stack, "magic"),
                    Catch::Contains("great_circle") && Catch::Contains("magic"));
}

TEST_CASE("evaluation rows and summaries, invalid rows counted but never scored",
          "[skypole][evaluate]") {
  testing::SyntheticSpec spec;
  spec.times = testing::paper_times();
  spec.size = 128;
  std::vector<skypole::EvaluationRow> rows;
  for (double heading : {0.0, 120.0}) {
    spec.heading_deg = heading;
    const render::Stack stack = testing::make_stack(spec);
    for (const auto& m : skypole::method_names())
      rows.push_back({"marseille_h" + std::to_string(static_cast<int>(heading)),
                      skypole::run_method(stack, m), stack.frames.front().truth});
  }
  rows.push_back({"broken, \"quoted\"", skypole::invalid_estimate("classic", "pole outside"),
                  rows.front().truth});
  const auto summaries = skypole::summarize(rows);
  REQUIRE(summaries.size() == skypole::method_names().size());
  CHECK(summaries[0].method == "classic");
  CHECK(summaries[0].rows == 3);
  CHECK(summaries[0].valid == 2);
  for (const auto& s : summaries) {
    CHECK(s.angular_deg.n == s.valid);
    CHECK(s.angular_deg.max < 2.0);
  }
  const std::string csv = skypole::rows_csv(rows);
  CHECK(csv.find("nan") == std::string::npos);
  CHECK(csv.find("\"broken, \"\"quoted\"\"\",classic,0,pole outside") != std::string::npos);
  const std::string sum = skypole::summary_csv(summaries);
  CHECK(sum.rfind("method,rows,valid,bearing_n", 0) == 0);
  std::cout << skypole::summary_text(summaries);
}
