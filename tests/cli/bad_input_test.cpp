// Bad input through the executable, one test per class (issue 7): malformed TOML, a wrong type,
// an unknown key, a missing file (include, sweep), a bad --set, a sweep axis that names no key, a
// shard outside 1..N; a value out of range and a missing scene are in cli_test.cpp. Each gives its message with the file, line,
// column and key, exits with code 2, and leaves nothing behind: no stack, no output folder.
#include <catch2/catch.hpp>

#include "cli/cli_harness.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string kScene = std::string(skypol::test::kMarseilleSite) + R"(
[time]
start = "2022-09-23T08:00:00Z"
end = "2022-09-23T12:00:00Z"
step_min = 120

[camera]
model = "equidistant"
focal_mm = 1.8
pitch_um = 55.2
width = 153
height = 128
fov_deg = 185
)";

std::string with(const std::string& from, const std::string& to) {
  std::string s = kScene;
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// `skypol render` on `text` (written as bad.toml, plus `extra` files): exit 2, `message` in the
// output, and no file written besides the inputs.
void expect_render_error(const std::string& text, const std::string& message, const std::string& args = "",
                         const std::vector<std::pair<std::string, std::string>>& extra = {}) {
  TempDir dir;
  for (const auto& [name, body] : extra) dir.write(name, body);
  const std::string scene = dir.write("bad.toml", text);
  const Result r = run("render " + scene + " -o " + (dir.path / "out.exr").string() + " " + args);
  INFO(r.out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains(message));
  CHECK_THAT(r.out, Catch::Contains(": error: "));
  CHECK(entries(dir.path) == 1 + extra.size());  // nothing written
}

}  // namespace

TEST_CASE("bad input: malformed TOML", "[cli][errors]") {
  expect_render_error(with("width = 153", "width = = 153"), "bad.toml:14:9: error: TOML syntax");
}

TEST_CASE("bad input: a value of the wrong type", "[cli][errors]") {
  expect_render_error(with("width = 153", "width = \"wide\""),
                      "bad.toml:14:9: error: key 'camera.width': expected an integer, found a string");
}

TEST_CASE("bad input: an unknown key, with the nearest known one", "[cli][errors]") {
  expect_render_error(with("fov_deg", "fov_dge"),
                      "bad.toml:16:1: error: unknown key 'camera.fov_dge' (did you mean 'camera.fov_deg'?)");
}

// A value out of range and a missing scene file: cli_test.cpp ("a bad scene exits non-zero …",
// "a missing scene or stack file is named").

TEST_CASE("bad input: missing files", "[cli][errors]") {
  expect_render_error("include = \"presets/none.toml\"\n" + std::string(kScene),
                      "bad.toml:1:11: error: key 'include': cannot open included file 'presets/none.toml'");
  const Result s = run("sweep /nonexistent/sweep.toml -o /nonexistent/out");
  CHECK(s.code == 2);
  CHECK_THAT(s.out, Catch::Contains("/nonexistent/sweep.toml: error: cannot open sweep file"));
}

TEST_CASE("bad input: an override on the command line", "[cli][errors]") {
  expect_render_error(kScene, "--set:1:16: error: key 'camera.fov_deg': value 400 out of range [1, 360]",
                      "--set camera.fov_deg=400");
  expect_render_error(kScene, "--set:1:8: error: unknown key 'camera.fovdeg' (did you mean 'camera.fov_deg'?)",
                      "--set camera.fovdeg=100");
}

TEST_CASE("bad input: a sweep axis that names no key", "[cli][errors]") {
  TempDir dir;
  dir.write("base.toml", kScene);
  const std::string sweep =
      dir.write("sweep.toml", "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = [0, 90]\n\"site.lattitude_deg\" = [0, 45]\n");
  const fs::path out = dir.path / "out";
  const Result r = run("sweep " + sweep + " -o " + out.string());
  INFO(r.out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains(sweep + ":4:24: error: unknown key 'site.lattitude_deg' (did you mean "
                                    "'site.latitude_deg'?) (axis 'site.lattitude_deg' = 0)"));
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("bad input: a shard outside 1..N", "[cli][errors]") {
  TempDir dir;
  dir.write("base.toml", kScene);
  const std::string sweep = dir.write("sweep.toml", "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = [0, 90]\n");
  const fs::path out = dir.path / "out";
  // Malformed shards ("two/3", "3", "0/3") are parse_shard's unit test (scene/sweep_test.cpp).
  const Result r = run("sweep " + sweep + " -o " + out.string() + " --shard 4/3");
  INFO(r.out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("error: --shard 4/3: shard 4 is outside 1..3"));
  CHECK_FALSE(fs::exists(out));
}
