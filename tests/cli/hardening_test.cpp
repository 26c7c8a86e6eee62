// The hardening issue's regressions, through the executable as a user runs it: each bad input is
// a located error with exit code 2 (never 3, never a filesystem_error), nothing is left behind,
// killed renders' leftovers are cleaned, and -o means what README.md says.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>

#include <sys/wait.h>
#include <unistd.h>

#include "cli/cli_harness.h"
#include "stack/stack_io.h"
#include "stack/temp_files.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::run_shell;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

const char* kSite = "[site]\nlatitude_deg = 43.28699\nlongitude_deg = 5.40336\n";
const char* kTime = "\n[time]\nstart = \"2022-09-23T08:00:00Z\"\nend = \"2022-09-23T12:00:00Z\"\nstep_min = 120\n";
const char* kCamera = R"(
[camera]
model = "equidistant"
focal_mm = 1.8
pitch_um = 55.2
width = 153
height = 128
fov_deg = 185
binning = 4
)";

std::string scene_text() { return std::string(kSite) + kTime + kCamera; }

std::set<std::string> names_in(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
  return out;
}

// `skypol ARGS`: exit 2 with `message` and a located error.
Result expect_error(const std::string& args, const std::string& message) {
  const Result r = run(args);
  INFO(args);
  INFO(r.out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains(message));
  CHECK_THAT(r.out, Catch::Contains("error: "));
  CHECK_THAT(r.out, !Catch::Contains("internal error"));
  return r;
}

// A PID that belongs to no live process: a child that has exited and been reaped.
std::string dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  REQUIRE(child > 0);
  ::waitpid(child, nullptr, 0);
  return std::to_string(child);
}

}  // namespace

TEST_CASE("an include name the file system refuses is a located scene error", "[cli][errors]") {
  TempDir dir;
  const std::string scene = dir.write("bad.toml", "include = \"" + std::string(300, 'a') + ".toml\"\n" + scene_text());
  expect_error("render " + scene + " -o " + (dir.path / "out.exr").string(),
               "bad.toml:1:11: error: key 'include': cannot open included file 'aaaa");
  CHECK(names_in(dir.path) == std::set<std::string>{"bad.toml"});
}

TEST_CASE("a missing section is reported at the file's first line, by name", "[cli][errors]") {
  TempDir dir;
  const std::string out = (dir.path / "out.exr").string();
  expect_error("render " + dir.write("a.toml", std::string(kTime) + kCamera) + " -o " + out,
               "a.toml:1:1: error: key 'site': missing section [site]");
  expect_error("render " + dir.write("b.toml", std::string(kSite) + kCamera) + " -o " + out,
               "b.toml:1:1: error: key 'time': missing section [time]");
  expect_error("render " + dir.write("c.toml", std::string(kSite) + kTime) + " -o " + out,
               "c.toml:1:1: error: key 'camera': missing section [camera]");
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("a sweep's missing base is reported at its base key", "[cli][errors]") {
  TempDir dir;
  const std::string sweep = dir.write("sweep.toml", "base = \"none.toml\"\n[axes]\n\"camera.heading_deg\" = [0, 90]\n");
  expect_error("sweep " + sweep + " -o " + (dir.path / "out").string(),
               sweep + ":1:8: error: key 'base': cannot open the base scene");
  CHECK_FALSE(fs::exists(dir.path / "out"));
}

TEST_CASE("--set on a sweep axis names the command line and the axis's line", "[cli][errors]") {
  TempDir dir;
  dir.write("base.toml", scene_text());
  const std::string sweep =
      dir.write("sweep.toml", "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = [0, 90]\n");
  expect_error("sweep " + sweep + " -o " + (dir.path / "out").string() + " --set camera.heading_deg=10",
               "--set:1:1: error: key 'camera.heading_deg': the command line's --set cannot set a sweep axis "
               "(axis 'camera.heading_deg' at " + sweep + ":3:");
  CHECK_FALSE(fs::exists(dir.path / "out"));
}

TEST_CASE("a sensor whose demosaic cannot work is a scene error at its key, before any work", "[cli][errors]") {
  TempDir dir;
  const std::string scene = dir.write("s.toml", scene_text() + "\n[sensor]\npreset = \"lucid_phx050s_qc\"\ncolor_filter = \"none\"\n");
  const std::string out = (dir.path / "out.exr").string();
  REQUIRE(run("render -q " + scene + " -o " + out).code == 0);  // the sensor itself is fine
  fs::remove(out);
  const Result r = expect_error("render -q " + scene + " -o " + out +
                                    " --set sensor.demosaic=calibrated --set sensor.mosaic_deg=[0,0,0,0]",
                                "--set:1:19: error: key 'sensor.mosaic_deg': mosaic_deg: the four polarizer angles do not "
                                "determine S1 and S2 (demosaic = \"calibrated\")");
  CHECK_THAT(r.out, !Catch::Contains("cannot write stack"));
  expect_error("render -q " + scene + " -o " + out + " --set sensor.mosaic_deg=[0,0,0,0]",
               "--set:1:19: error: key 'sensor.mosaic_deg': mosaic_deg must hold 0, 45, 90 and 135");
  CHECK(names_in(dir.path) == std::set<std::string>{"s.toml"});
}

TEST_CASE("previews into a folder that cannot be written are a clear error, nothing left", "[cli][errors]") {
  TempDir dir;
  const std::string scene = dir.write("p.toml", scene_text() + "\n[output]\npreviews = true\n");
  dir.write("file", "a regular file");
  // A folder whose parent is a regular file (ENOTDIR, also for root), and /proc (read-only for root).
  const std::string under_file = (dir.path / "file" / "x.exr").string();
  expect_error("render -q " + scene + " -o " + under_file, (dir.path / "file" / "x-preview").string() +
                                                               ": error: cannot write the previews: cannot create");
  expect_error("render -q " + scene + " -o /proc/skypol-x.exr", "/proc/skypol-x-preview: error: cannot write the previews");
  CHECK_FALSE(fs::exists("/proc/skypol-x.exr"));
  CHECK(names_in(dir.path) == std::set<std::string>{"p.toml", "file"});

  // `skypol preview` of a good stack, into the same kinds of folder.
  const std::string stack = (dir.path / "ok.exr").string();
  REQUIRE(run("render -q " + scene + " -o " + stack).code == 0);
  REQUIRE(fs::is_directory(dir.path / "ok-preview"));
  expect_error("preview " + stack + " -o " + (dir.path / "file" / "pv").string(),
               (dir.path / "file" / "pv").string() + ": error: cannot write the previews: cannot create");
  expect_error("preview " + stack + " -o /proc/skypol-pv", "/proc/skypol-pv: error: cannot write the previews");
  CHECK(names_in(dir.path) == std::set<std::string>{"p.toml", "file", "ok.exr", "ok-preview"});
}

TEST_CASE("a render removes its target's leftovers of this host's dead processes, no one else's", "[cli][leftovers]") {
  TempDir dir;
  const std::string scene = dir.write("p.toml", scene_text() + "\n[output]\npreviews = true\n");
  const std::string host = skypol::stack::host_name(), dead = dead_pid();
  const std::string mine = "out.exr.tmp-" + host + "-" + dead, preview = ".out-preview.tmp-" + host + "-" + dead;
  const std::string other_host = "out.exr.tmp-some-other-node-" + dead, other_file = "else.exr.tmp-" + host + "-" + dead;
  for (const std::string& n : {mine, other_host, other_file}) dir.write(n, "half a stack");
  fs::create_directories(dir.path / preview);
  dir.write(preview + "/0000.png", "half a picture");
  const Result r = run("render -q " + scene + " -o " + (dir.path / "out.exr").string());
  INFO(r.out);
  REQUIRE(r.code == 0);
  CHECK(names_in(dir.path) == std::set<std::string>{"p.toml", "out.exr", "out-preview", other_host, other_file});
}

TEST_CASE("-o names a file, or a folder that receives <scene name>.exr; -o \"\" is refused", "[cli][output]") {
  TempDir dir;
  const std::string scene = dir.write("zen.toml", scene_text());
  // A name ending in '/' (the folder is made) and an existing folder.
  REQUIRE(run("render -q " + scene + " -o " + (dir.path / "new").string() + "/").code == 0);
  CHECK(fs::is_regular_file(dir.path / "new" / "zen.exr"));
  fs::create_directories(dir.path / "old");
  REQUIRE(run("render -q " + scene + " -o " + (dir.path / "old").string()).code == 0);
  CHECK(fs::is_regular_file(dir.path / "old" / "zen.exr"));
  CHECK(names_in(dir.path / "new") == std::set<std::string>{"zen.exr"});
  // -o "" would have written the scene's output.path (out/zen.exr, relative to the working folder).
  const Result r = run_shell("cd " + dir.path.string() + " && " + skypol::test::skypol_bin() + " render -q zen.toml -o ''");
  INFO(r.out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("error: -o: the output path is empty"));
  CHECK_FALSE(fs::exists(dir.path / "out"));
}

TEST_CASE("estimate --intermediates that cannot be written names the stack and the reason", "[cli][errors]") {
  TempDir dir;
  const std::string scene = dir.write("e.toml", scene_text());
  const std::string stack = (dir.path / "e.exr").string();
  REQUIRE(run("render -q " + scene + " -o " + stack).code == 0);
  dir.write("file", "a regular file");
  const std::string inter = (dir.path / "file" / "classic.exr").string();
  const Result r = expect_error("estimate " + stack + " --intermediates " + inter,
                                stack + ": cannot write the classic intermediates to " + inter + ": ");
  // The reason is not empty: something follows the last ": ".
  const std::string line = r.out.substr(r.out.find("cannot write the classic intermediates"));
  CHECK(line.find_first_not_of(" \n", line.rfind(": ") + 1) != std::string::npos);
  CHECK(names_in(dir.path) == std::set<std::string>{"e.toml", "e.exr", "file"});
}

TEST_CASE("a half stack of the sun at the zenith holds no Inf: the disc is clamped to 65504", "[cli][half]") {
  // The subsolar point of scenes/hard-sun-zenith.toml; an odd-sized image puts the optical axis,
  // and so the sun, on the centre pixel's centre, whose ray meets the disc (radiance 2e5).
  TempDir dir;
  const std::string scene = dir.write("z.toml", R"([site]
latitude_deg = 23.437762
longitude_deg = 0.45483
[time]
instants = ["2022-06-21T12:00:00Z"]
[camera]
model = "equidistant"
fx = 30
width = 101
height = 101
fov_deg = 185
[sky]
sun_disc = true
[output]
pixel_type = "half"
)");
  const std::string out = (dir.path / "zenith.exr").string();
  const Result r = run("render -q " + scene + " -o " + out);
  INFO(r.out);
  REQUIRE(r.code == 0);
  const skypol::stack::Stack st = skypol::stack::read_stack(out);
  REQUIRE(st.frames.size() == 1);
  float highest = 0;
  for (const auto& [name, values] : st.frames[0].channels) {
    for (float v : values) {
      REQUIRE(std::isfinite(v));
      if (name.rfind("S0.", 0) == 0) highest = std::max(highest, v);
    }
  }
  CHECK(highest == 65504.0f);  // the disc, clamped
  CHECK(st.frames[0].channel("S0.Y")[50 * 101 + 50] == 65504.0f);
}
