// EXR stacks: what is written is read back bit for bit with its truth; a failed write leaves
// nothing behind; a file that is not a skypol stack is refused with its name.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "render/pipeline.h"
#include "stack/stack_io.h"
#include "stack/temp_files.h"

#include <set>
#include <sys/wait.h>
#include <unistd.h>

using namespace skypol;
namespace fs = std::filesystem;

namespace {

const char* kScene = R"([site]
latitude_deg = -33.8568
longitude_deg = 151.2153

[time]
instants = ["2023-01-10T01:00:00Z", "2023-01-10T02:30:00Z", "2023-01-10T04:00:00Z"]

[camera]
model = "equidistant"
fx = 20
width = 70
height = 60
fov_deg = 185
heading_deg = 200
tilt_deg = 5
)";

fs::path temp_dir() {
  fs::path d = fs::temp_directory_path() / ("skypol-test-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE("a rendered stack reads back with its pixels and truth", "[stack]") {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "sydney.exr").string();
  const scene::Scene scene = scene::parse_scene(kScene, "sydney.toml");
  render::render_scene(scene, path);
  const stack::Stack stack = stack::read_stack(path);
  REQUIRE(stack.frames.size() == 3);
  CHECK(stack.bands == std::vector<std::string>{"Y"});
  CHECK(stack.scene_text == kScene);
  CHECK(stack.camera->width() == 70);
  CHECK(stack.camera->lens().intrinsics().fx == 20);
  const stack::Frame& f = stack.frames[1];
  CHECK(f.width == 70);
  CHECK(f.height == 60);
  for (const char* c : {"S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y", "mask"}) CHECK(f.has(c));
  CHECK(sky::format_iso8601(f.truth.time) == "2023-01-10T02:30:00Z");
  CHECK(f.truth.site.latitude_deg == -33.8568);
  CHECK(f.truth.heading_deg == 200);
  CHECK(f.truth.tilt_deg == 5);
  CHECK_FALSE(f.truth.pole_is_north);  // Sydney sees the south celestial pole
  CHECK(f.truth.pole_enu.z() == Approx(std::sin(33.8568 * M_PI / 180)));
  CHECK(f.truth.pole_enu.y() < 0);
  // The sun in the header is the one ERFA gives for that instant.
  const sky::Sun sun = sky::sun_position(scene.site, f.truth.time);
  CHECK(f.truth.sun.azimuth == Approx(sun.azimuth).epsilon(1e-12));
  CHECK(f.truth.sun.declination == Approx(sun.declination).epsilon(1e-12));
  // The pixels equal a fresh render of that frame.
  const stack::Frame again = stack::read_stack(path, {"DoLP.Y"}).frames[1];
  CHECK(again.channels.size() == 1);
  CHECK(again.channel("DoLP.Y") == f.channel("DoLP.Y"));
  fs::remove_all(dir);
}

TEST_CASE("a write that fails leaves no file behind", "[stack][errors]") {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "broken.exr").string();
  scene::Truth t;
  std::vector<scene::Truth> truths(2, t);
  truths[1].time.unix_seconds = 60;
  CHECK_THROWS(stack::write_stack(path, truths, {"mask"}, 4, 3, {}, {}, [](std::size_t i) -> stack::Frame {
    if (i == 1) throw std::runtime_error("renderer failed");
    stack::Frame f;
    f.width = 4;
    f.height = 3;
    f.channels["mask"] = std::vector<float>(12, 1.0f);
    return f;
  }));
  CHECK_FALSE(fs::exists(path));
  CHECK(fs::is_empty(dir));  // no temporary either
  fs::remove_all(dir);
}

TEST_CASE("temporaries carry host and PID; only this host's dead leftovers are stale", "[stack][temporaries]") {
  const fs::path dir = temp_dir() / "tmpnames";
  fs::create_directories(dir);
  const std::string host = stack::host_name();
  CHECK(host.find('/') == std::string::npos);
  const std::string target = (dir / "a.exr").string();
  CHECK(stack::temp_name(target) == target + ".tmp-" + host + "-" + std::to_string(::getpid()));
  // A PID that surely belongs to no live process: a child that has exited and been reaped.
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  REQUIRE(child > 0);
  ::waitpid(child, nullptr, 0);
  const std::string dead = std::to_string(child), alive = std::to_string(::getpid());
  for (const std::string& name : {"a.exr.tmp-" + host + "-" + dead, "a.exr.tmp-" + host + "-" + alive,
                                  "a.exr.tmp-elsewhere-" + dead, "a.exr.tmp-" + dead, "b.exr.tmp-" + host + "-" + dead}) {
    std::ofstream(dir / name) << "x";
  }
  fs::create_directories(dir / (".a-preview.tmp-" + host + "-" + dead));
  const auto stale = stack::stale_temporaries(dir);
  REQUIRE(stale.count("a.exr") == 1);
  CHECK(stale.at("a.exr") == std::vector<fs::path>{dir / ("a.exr.tmp-" + host + "-" + dead)});
  CHECK(stale.count("b.exr") == 1);
  CHECK(stale.count(".a-preview") == 1);
  CHECK(stale.size() == 3);
  stack::remove_stale_temporaries(target);
  stack::remove_stale_temporaries((dir / ".a-preview").string());
  std::set<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.insert(e.path().filename().string());
  CHECK(left == std::set<std::string>{"a.exr.tmp-" + host + "-" + alive, "a.exr.tmp-elsewhere-" + dead,
                                      "a.exr.tmp-" + dead, "b.exr.tmp-" + host + "-" + dead});
  fs::remove_all(dir);
}

TEST_CASE("a file that is not a stack is refused with its name", "[stack][errors]") {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "not-an-exr.exr").string();
  std::ofstream(path) << "hello";
  try {
    stack::read_stack(path);
    FAIL("no error");
  } catch (const scene::SceneError& e) {
    CHECK_THAT(e.what(), Catch::StartsWith(path + ": error: cannot read stack"));
  }
  fs::remove_all(dir);
}

TEST_CASE("asking for a channel a stack lacks names it and the ones it has", "[stack][errors]") {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "s.exr").string();
  render::render_scene(scene::parse_scene(kScene, "sydney.toml"), path);
  try {
    stack::read_stack(path, {"DoLP.R"});
    FAIL("no error");
  } catch (const scene::SceneError& e) {
    CHECK_THAT(e.what(), Catch::Contains("no channel 'DoLP.R'"));
    CHECK_THAT(e.what(), Catch::Contains("DoLP.Y"));
  }
  fs::remove_all(dir);
}
