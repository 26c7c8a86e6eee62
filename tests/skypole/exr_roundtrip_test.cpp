// The whole chain: a scene rendered by render::render_scene, written as an EXR stack, read back by
// stack::read_stack (truth from the headers), estimated and scored. Checks that skypole and the
// renderer agree on every convention (heading, pole, frames, channels).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "render/pipeline.h"
#include "scene/scene.h"
#include "stack/stack_io.h"
#include "skypole/evaluate.h"

using namespace skypol;

TEST_CASE("estimators on a rendered, written and re-read EXR stack", "[skypole][exr]") {
  // The paper's Marseille set-up, shrunk to 256×256 (image circle of 185° touching the borders:
  // fx = 128 px / 92.5° = 79.28 px = 0.27352 mm at 3.45 µm), heading 37°.
  const std::string text = R"(
[site]
latitude_deg = 43.28699
longitude_deg = 5.40336
height_m = 60

[time]
start = "2022-09-23T08:00:00Z"
end = "2022-09-23T16:00:00Z"
step_min = 30

[camera]
model = "equidistant"
focal_mm = 0.273515
pitch_um = 3.45
width = 256
height = 256
fov_deg = 185
heading_deg = 37
tilt_deg = 0

[sky]
model = "rayleigh"
max_dolp = 1.0

[output]
path = "unused.exr"
channels = ["DoLP", "AoLP", "mask"]
)";
  const auto dir = std::filesystem::temp_directory_path() / "skypole_exr_roundtrip";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "marseille.exr").string();
  const scene::Scene scene = scene::parse_scene(text, "roundtrip.toml");
  render::render_scene(scene, path);
  const stack::Stack stack = stack::read_stack(path);
  REQUIRE(stack.frames.size() == 17);
  std::vector<skypole::EvaluationRow> rows;
  for (const auto& m : skypole::method_names())
    rows.push_back({"marseille.exr", skypole::run_method(stack, m), stack.frames.front().truth});
  const auto summaries = skypole::summarize(rows);
  std::cout << skypole::summary_text(summaries);
  for (const auto& s : summaries) {
    INFO(s.method);
    CHECK(s.valid == 1);
    CHECK(s.angular_deg.max < (s.method == "classic" ? 2.0 : 0.05));
    CHECK(s.bearing_abs_deg.max < (s.method == "classic" ? 2.0 : 0.1));
  }
  std::filesystem::remove_all(dir);
}
