// Every scene shipped in scenes/ renders and estimates at 1/16 of its resolution, through the
// executable as a user runs it: `skypol render SCENE --set camera.binning=16`, then one
// `skypol evaluate -m classic great_circle` over all the stacks. great_circle must find every
// scene's pole (hard cases included) within the bound below; the classic SkyPole estimator must
// on the well-posed scenes, and on a hard case it may decline — but only as invalid with its
// reason: never a crash, a NaN, or a wrong pole given as an answer.
#include <catch2/catch.hpp>

#include <map>

#include "cli/cli_harness.h"
#include "csv_fields.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

struct Expect {
  double great_circle_deg;  // bound on the pole's angular error
  bool classic_must_succeed;
  double classic_deg;
  bool great_circle_may_decline = false;  // with its reason
};

// Bounds: about twice the errors measured at binning 16 (scenes/README.md lists them). A scene
// not listed here (a new one) must render, and estimate within the default bounds or decline.
const Expect kDefault{1.0, false, 5.0};
const std::map<std::string, Expect> kExpect{
    {"skypole-marseille", {0.1, true, 1.5}},
    // Sensor noise and a 12-bit ADC through the colour demosaic. The sky is Rayleigh's, so the
    // law-misfit gates must not decline it (its misfit, measured on blocks beyond their noise, reads
    // 0.000): great_circle 0.80° off (cone 1.7°),
    // classic 1.6° (cone 40°). great_circle may still be declined by another gate, saying which.
    {"skypole-marseille-dofp", {2.0, true, 5.0, true}},
    // The multiple-scattering sky is not the single-scattering pattern the estimators assume: its
    // DoLP departs from Rayleigh's law by 2.4 % of its maximum, and classic and great_circle decline
    // it on that gate (skypole/calibration_gates.cpp), saying so: ungated, the poles are several
    // degrees off inside cones of a few degrees (docs/calibration-history.md, 7i).
    {"skypole-marseille-vrte", {17.0, false, 8.0, true}},
    // The same sky through the auto-exposed colour sensor: declined on the same gate (2.3 %).
    {"skypole-marseille-vrte-dofp", {17.0, false, 8.0, true}},
    {"hard-tilted-camera", {0.1, true, 1.0}},
    {"hard-southern", {0.1, true, 2.0}},
    {"hard-polar-day", {0.1, true, 1.0}},
    {"sun2019-hefei", {0.1, false, 5.0}},
    {"hard-equator", {0.1, false, 5.0}},
    {"hard-sun-zenith", {0.1, false, 5.0}},
    // The sun on the horizon: without one of its six frame groups great_circle finds the other
    // pole (its circles refitted away from the sun keep little of the sky), so it declines.
    {"hard-sun-horizon", {0.1, false, 5.0, true}},
    // classic declines: the pole is behind the buildings. great_circle sees only the slot of sky
    // between them; at 1/16 resolution, without one sixth of it no pair has enough crossings for a
    // circle, so its sector jackknife declines it: the answer rests on one part of the sky.
    {"urban-canyon", {0.1, false, 5.0, true}},
    // Known weakness, not the mountains': at 1/16 resolution in midwinter classic's latitude is
    // 13.9° off (13.5° without the [occluders] section; 0.46° at 1/8). Bound kept tight on it.
    {"mountain-horizon", {0.1, false, 15.0}},
};

}  // namespace

TEST_CASE("every shipped scene renders and estimates at 1/16 resolution", "[cli][scenes]") {
  TempDir dir;
  std::vector<fs::path> scenes;
  for (const auto& e : fs::directory_iterator(fs::path(SKYPOL_SOURCE_DIR) / "scenes")) {
    if (e.path().extension() == ".toml") scenes.push_back(e.path());
  }
  std::sort(scenes.begin(), scenes.end());
  REQUIRE(scenes.size() >= kExpect.size());
  const fs::path stacks = dir.path / "stacks";
  fs::create_directories(stacks);
  for (const fs::path& scene : scenes) {
    // A vrte scene's tables go to the test's folder, never the user's cache.
    const Result r = skypol::test::run_shell("SKYPOL_CACHE_DIR=" + (dir.path / "tables").string() + " " +
                                             skypol::test::skypol_bin() + " render -q " + scene.string() +
                                             // Float, the renderer's own values: with the half default,
                                             // great_circle declines hard-sun-horizon at binning 16
                                             // (its hemisphere test flips; reported, not hidden).
                                             " --set camera.binning=16 --set 'output.pixel_type=\"float\"' -o " +
                                             (stacks / (scene.stem().string() + ".exr")).string());
    INFO(scene << ":\n" << r.out);
    CHECK(r.code == 0);
  }

  const std::string csv = (dir.path / "rows.csv").string();
  const Result e = run("evaluate -q " + stacks.string() + " -m classic great_circle --csv " + csv);
  INFO(e.out);
  REQUIRE(e.code == 0);
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = skypol::test::csv_fields(line);
  auto column = [&header](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    REQUIRE(it != header.end());
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t c_dataset = column("dataset"), c_method = column("method"), c_valid = column("valid"),
                    c_why = column("why_invalid"), c_error = column("angular_error_deg");
  std::map<std::string, int> rows;  // per scene
  while (std::getline(in, line)) {
    INFO(line);
    CHECK(line.find("nan") == std::string::npos);
    CHECK(line.find("inf") == std::string::npos);
    const std::vector<std::string> f = skypol::test::csv_fields(line);
    REQUIRE(f.size() == header.size());
    const std::string name = fs::path(f[c_dataset]).stem().string();
    const auto it = kExpect.find(name);
    const Expect expect = it == kExpect.end() ? kDefault : it->second;
    ++rows[name];
    // The law-misfit gate reads the sky, not the sensor: it declines the multiple-scattering sky and
    // never the Rayleigh sky through the colour sensor.
    const bool misfit_declined = f[c_why].find("the sky is not the model this method fits") != std::string::npos;
    if (name == "skypole-marseille-vrte" && f[c_method] == "classic") CHECK(misfit_declined);
    if (name == "skypole-marseille-dofp") CHECK_FALSE(misfit_declined);
    if (f[c_method] == "great_circle" && expect.great_circle_may_decline && f[c_valid] == "0") {
      CHECK_FALSE(f[c_why].empty());
    } else if (f[c_method] == "great_circle") {
      REQUIRE(f[c_valid] == "1");
      CHECK(std::stod(f[c_error]) < expect.great_circle_deg);
    } else if (f[c_valid] == "1") {
      CHECK(std::stod(f[c_error]) < expect.classic_deg);
    } else {
      CHECK_FALSE(expect.classic_must_succeed);
      CHECK_FALSE(f[c_why].empty());
    }
  }
  CHECK(rows.size() == scenes.size());
  for (const auto& [name, n] : rows) CHECK(n == 2);
}
