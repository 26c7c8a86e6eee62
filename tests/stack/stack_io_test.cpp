// EXR stacks: what is written is read back bit for bit with its truth; a failed write leaves
// nothing behind; a file that is not a skypol stack is refused with its name.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "render/pipeline.h"
#include "stack/stack_io.h"

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

namespace {
std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
}  // namespace

TEST_CASE("a stack rendered after another, in that one's memory, is the file a fresh process writes", "[stack]") {
  // render_scene keeps its frame for the next stack on the same thread (render/pipeline.cpp); a
  // new thread starts with none, as a new process does.
  const fs::path dir = temp_dir();
  std::string other = kScene;
  other.replace(other.find("width = 70\nheight = 60"), 22, "width = 90\nheight = 50");
  other += "\n[output]\nchannels = [\"DoLP\", \"mask\"]\n";
  auto fresh = [&](const std::string& text, const fs::path& path) {
    std::thread([&] { render::render_scene(scene::parse_scene(text, "fresh.toml"), path.string()); }).join();
  };
  fresh(kScene, dir / "fresh-a.exr");
  fresh(other, dir / "fresh-b.exr");
  // One thread, in turn: bigger to smaller and fewer channels, then back.
  std::thread([&] {
    render::render_scene(scene::parse_scene(kScene, "fresh.toml"), (dir / "a1.exr").string());
    render::render_scene(scene::parse_scene(other, "fresh.toml"), (dir / "b.exr").string());
    render::render_scene(scene::parse_scene(kScene, "fresh.toml"), (dir / "a2.exr").string());
  }).join();
  CHECK(file_bytes((dir / "b.exr").string()) == file_bytes((dir / "fresh-b.exr").string()));
  CHECK(file_bytes((dir / "a2.exr").string()) == file_bytes((dir / "fresh-a.exr").string()));
  CHECK(file_bytes((dir / "a1.exr").string()) == file_bytes((dir / "fresh-a.exr").string()));
  fs::remove_all(dir);
}
