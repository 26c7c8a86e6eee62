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
  stack::Stack stack;
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
    const stack::Stack stack = testing::make_stack(spec);
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

TEST_CASE("accuracy of every method: noise-free day, noisy day, noisy short window",
          "[skypole][evaluate][accuracy]") {
  // The targets: better estimators within 0.05° on noise-free Rayleigh stacks of the
  // paper's set-up; with realistic sensor noise ≤ 0.3° from a shorter window.
  struct Case {
    const char* name;
    const char* start;
    const char* end;
    double step_min;
    double noise;
    double pmax;
  };
  const Case cases[] = {
      {"paper day, noise-free", "2022-09-23T08:00:00Z", "2022-09-23T16:00:00Z", 30, 0, 1.0},
      {"paper day, noise 1%, Pmax 0.7", "2022-09-23T08:00:00Z", "2022-09-23T16:00:00Z", 30, 0.01, 0.7},
      {"2 h every 10 min, noise 1%, Pmax 0.7", "2022-09-23T09:00:00Z", "2022-09-23T11:00:00Z", 10, 0.01, 0.7},
  };
  for (const Case& c : cases) {
    std::vector<skypole::EvaluationRow> rows;
    for (double heading : {15.0, 140.0, 260.0}) {
      testing::SyntheticSpec spec;
      spec.times = testing::times_every(c.start, c.end, c.step_min);
      spec.heading_deg = heading;
      spec.noise = c.noise;
      spec.max_dolp = c.pmax;
      spec.seed = static_cast<std::uint32_t>(heading) + 7;
      const stack::Stack stack = testing::make_stack(spec);
      for (const auto& m : skypole::method_names())
        rows.push_back({c.name, skypole::run_method(stack, m), stack.frames.front().truth});
    }
    const auto summaries = skypole::summarize(rows);
    std::cout << "\n" << c.name << " (3 headings, 256×256 equidistant 185°):\n"
              << skypole::summary_text(summaries);
    for (const auto& r : rows)
      if (!r.estimate.valid) std::cout << "  invalid " << r.estimate.method << ": " << r.estimate.why_invalid << "\n";
    for (const auto& s : summaries) {
      INFO(c.name << " / " << s.method);
      if (c.noise == 0 && s.method != "classic") CHECK(s.angular_deg.max < 0.05);
      if (c.noise > 0 && (s.method == "sun_vector" || s.method == "sun_dolp" || s.method == "invariance"))
        CHECK(s.angular_deg.max < 0.3);
    }
  }
}

TEST_CASE("run time on a larger image", "[.perf]") {
  // Not run by default: a 2048×2048, 17-frame stack (the paper's sensor is 2448×2048).
  testing::SyntheticSpec spec;
  spec.times = testing::paper_times();
  spec.size = 2048;
  const stack::Stack stack = testing::make_stack(spec);
  for (const auto& m : skypole::method_names()) {
    const skypole::PoleEstimate e = skypole::run_method(stack, m);
    const skypole::Score s = skypole::score(e, stack.frames.front().truth);
    std::cout << m << ": " << e.seconds << " s, angular " << s.angular_error_deg << "\n";
  }
}

TEST_CASE("hard sites: a geographic pole and the equator", "[skypole][evaluate]") {
  SECTION("north pole at midsummer: latitude 90, no bearing from anyone") {
    testing::SyntheticSpec spec;
    spec.latitude_deg = 90;
    spec.times = testing::times_every("2022-06-21T00:00:00Z", "2022-06-21T08:00:00Z", 30);
    spec.size = 128;
    const stack::Stack stack = testing::make_stack(spec);
    for (const auto& m : skypole::method_names()) {
      const skypole::PoleEstimate e = skypole::run_method(stack, m);
      INFO(m << ": " << e.why_invalid);
      REQUIRE(e.valid);
      CHECK(e.latitude_deg > 88);
      const skypole::Score s = skypole::score(e, stack.frames.front().truth);
      CHECK_FALSE(s.bearing_error_deg.has_value());
      if (m != "classic" && m != "invariance") CHECK_FALSE(e.heading_deg.has_value());
    }
  }
  SECTION("equator at the equinox: the pole on the horizon") {
    testing::SyntheticSpec spec;
    spec.latitude_deg = 0.0;
    spec.longitude_deg = 0.0;
    spec.heading_deg = 50;
    spec.times = testing::paper_times();
    spec.size = 128;
    const stack::Stack stack = testing::make_stack(spec);
    for (const auto& m : {"great_circle", "sun_vector", "sun_dolp"}) {
      const skypole::PoleEstimate e = skypole::run_method(stack, m);
      INFO(m << ": " << e.why_invalid);
      REQUIRE(e.valid);
      const skypole::Score s = skypole::score(e, stack.frames.front().truth);
      std::cout << "equator " << m << ": angular " << s.angular_error_deg << "°, north "
                << e.is_north << "\n";
      CHECK(s.angular_error_deg < 0.1);
    }
    // The image-space methods need the pole inside the usable image: a clear refusal or a pole
    // near the horizon, never a silent far-off number.
    for (const auto& m : {"classic", "invariance"}) {
      const skypole::PoleEstimate e = skypole::run_method(stack, m);
      std::cout << "equator " << m << ": " << (e.valid ? "valid" : e.why_invalid) << "\n";
      if (e.valid) CHECK(skypole::score(e, stack.frames.front().truth).angular_error_deg < 3);
    }
  }
}
