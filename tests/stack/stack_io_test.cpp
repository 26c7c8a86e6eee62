// EXR stacks: what is written is read back bit for bit with its truth; a failed write leaves
// nothing behind; a file that is not a skypol stack is refused with its name.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <tuple>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "render/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_error.h"
#include "scene/truth.h"
#include "sky/units.h"
#include "stack/stack_io.h"
#include "stack/temp_files.h"
#include "test_files.h"

#include <OpenImageIO/imageio.h>
#include <limits>
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

fs::path temp_dir() { return test::temp_dir("skypol-test"); }
using test::file_bytes;

// n parts' truths, a minute apart: all the stack writers need of them.
std::vector<scene::Truth> truths_every_minute(std::size_t n) {
  std::vector<scene::Truth> truths(n);
  for (std::size_t i = 0; i < n; ++i) truths[i].time.unix_seconds = 60.0 * static_cast<double>(i);
  return truths;
}

}  // namespace

TEST_CASE("a rendered stack reads back with its pixels and truth", "[stack]") {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "sydney.exr").string();
  // Float: the pixels are compared bit for bit with a fresh render below (the default is half).
  const std::string text = std::string(kScene) + "[output]\npixel_type = \"float\"\n";
  const scene::Scene scene = scene::parse_scene(text, "sydney.toml");
  render::render_scene(scene, path);
  const stack::Stack stack = stack::read_stack(path);
  REQUIRE(stack.frames.size() == 3);
  CHECK(stack.bands == std::vector<std::string>{"Y"});
  CHECK(stack.scene_text == text);
  CHECK(stack.camera->width() == 70);
  CHECK(stack.camera->lens().intrinsics().fx == 20);
  const stack::Frame& f = stack.frames[1];
  CHECK(f.width == 70);
  CHECK(f.height == 60);
  for (const char* c : {"S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y", "mask"}) CHECK(f.has(c));
  // Every truth field against a value computed here from the scene, not read from the file: the
  // instant and site from the scene text, the sun from ERFA, the orientation and the pole's pixel
  // from the camera the scene builds.
  const sky::Instant when = sky::parse_iso8601("2023-01-10T02:30:00Z");
  CHECK(f.truth.time.unix_seconds == when.unix_seconds);
  CHECK(sky::format_iso8601(f.truth.time) == "2023-01-10T02:30:00Z");
  CHECK(f.truth.site.latitude_deg == -33.8568);
  CHECK(f.truth.site.longitude_deg == 151.2153);
  CHECK(f.truth.site.height_m == 0);
  CHECK(f.truth.heading_deg == 200);
  CHECK(f.truth.tilt_deg == 5);
  CHECK(f.truth.roll_deg == 0);
  CHECK_FALSE(f.truth.pole_is_north);  // Sydney sees the south celestial pole
  const Eigen::Vector3d pole(0, -std::cos(rad_from_deg(33.8568)), std::sin(rad_from_deg(33.8568)));
  CHECK((f.truth.pole_enu - pole).norm() < 1e-12);
  // The sun in the header is the one ERFA gives for that instant (with the scene's options).
  const sky::Sun sun = sky::sun_position(scene.site, when, scene.sun_options);
  CHECK(f.truth.sun.azimuth == Approx(sun.azimuth).epsilon(1e-12));
  CHECK(f.truth.sun.elevation == Approx(sun.elevation).epsilon(1e-12));
  CHECK(f.truth.sun.declination == Approx(sun.declination).epsilon(1e-12));
  CHECK(f.truth.sun.hour_angle == Approx(sun.hour_angle).epsilon(1e-12));
  CHECK((f.truth.sun.direction - sun.direction).norm() < 1e-12);
  // ENU from azimuth and elevation (docs/conventions.md), a second, independent check.
  const Eigen::Vector3d toward(std::sin(sun.azimuth) * std::cos(sun.elevation),
                               std::cos(sun.azimuth) * std::cos(sun.elevation), std::sin(sun.elevation));
  CHECK((f.truth.sun.direction - toward).norm() < 1e-9);
  const std::shared_ptr<const camera::Camera> cam = scene::build_camera(scene.camera);
  CHECK((f.truth.world_from_camera - cam->world_from_camera()).norm() < 1e-12);
  const std::optional<Eigen::Vector2d> pole_px = cam->project(pole);
  REQUIRE(pole_px.has_value());
  REQUIRE(f.truth.pole_pixel.has_value());
  CHECK((*f.truth.pole_pixel - *pole_px).norm() < 1e-9);
  // The pixels equal a fresh render of that frame, made here in memory.
  render::RenderOptions ro;
  ro.bands = scene.render.bands;
  ro.channels = scene.output.channels;
  const render::Renderer renderer(cam, ro);
  const stack::Frame fresh = renderer.render(*scene::build_sky(scene.sky), sun);
  for (const char* c : {"S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y", "mask"}) {
    INFO(c);
    CHECK(fresh.channel(c) == f.channel(c));
  }
  // Reading only some channels reads those alone, with the same values.
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

TEST_CASE("a half stack clamps values beyond half's range to +-65504 and says so", "[stack][half]") {
  // The sun disc at the zenith has a radiance of ~2e5, beyond half's largest value (65504): the
  // writer clamps (docs/exr-format.md) instead of writing +Inf.
  const fs::path dir = temp_dir();
  const std::string path = (dir / "half.exr").string();
  const scene::Scene scene = scene::parse_scene(kScene, "sydney.toml");
  const std::shared_ptr<const camera::Camera> cam = scene::build_camera(scene.camera);
  const int w = cam->width(), h = cam->height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<scene::Truth> truths{scene::make_truth(scene, *cam, scene.times[0])};
  stack::StackHeader header;
  header.bands = {"Y"};
  header.camera_description = scene.camera.description;
  header.scene_text = kScene;
  header.sky_model = "test";
  stack::WriteOptions wo;
  wo.half = true;
  stack::write_stack(path, truths, {"S0.Y", "S1.Y", "mask"}, w, h, header, wo, [&](std::size_t) {
    stack::Frame f;
    f.width = w;
    f.height = h;
    f.channels["S0.Y"] = std::vector<float>(n, 0.5f);
    f.channels["S0.Y"][7] = 2e5f;
    f.channels["S0.Y"][8] = std::numeric_limits<float>::max();
    f.channels["S1.Y"] = std::vector<float>(n, -0.25f);
    f.channels["S1.Y"][7] = -1e6f;
    f.channels["mask"] = std::vector<float>(n, 1.0f);
    f.channels["mask"][9] = 1e6f;  // the mask stays float: never clamped
    return f;
  });
  const stack::Stack st = stack::read_stack(path);
  const stack::Frame& f = st.frames.at(0);
  for (const auto& [name, values] : f.channels) {
    for (float v : values) REQUIRE(std::isfinite(v));
  }
  CHECK(f.channel("S0.Y")[7] == 65504.0f);
  CHECK(f.channel("S0.Y")[8] == 65504.0f);
  CHECK(f.channel("S0.Y")[0] == 0.5f);
  CHECK(f.channel("S1.Y")[7] == -65504.0f);
  CHECK(f.channel("S1.Y")[0] == -0.25f);
  CHECK(f.channel("mask")[9] == 1e6f);
  auto in = OIIO::ImageInput::open(path);
  REQUIRE(in);
  CHECK(in->spec().get_float_attribute("skypol:halfClamp", 0) == 65504.0f);
  in.reset();
  // A float stack keeps every value and carries no such attribute.
  wo.half = false;
  stack::write_stack(path, truths, {"S0.Y"}, w, h, header, wo, [&](std::size_t) {
    stack::Frame g;
    g.width = w;
    g.height = h;
    g.channels["S0.Y"] = std::vector<float>(n, 2e5f);
    return g;
  });
  CHECK(stack::read_stack(path).frames.at(0).channel("S0.Y")[3] == 2e5f);
  auto in2 = OIIO::ImageInput::open(path);
  REQUIRE(in2);
  CHECK(in2->spec().get_float_attribute("skypol:halfClamp", 0) == 0.0f);
  in2.reset();
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

TEST_CASE("a later stack with the same camera reuses its rays and writes the file a fresh process writes", "[stack]") {
  // render_scene keeps the last stack's rays for a next stack with the same camera (a sweep's
  // variants that change only the sky or the times): that stack's file must not change.
  const fs::path dir = temp_dir();
  const std::string first = std::string(kScene) + "\n[sky]\nmax_dolp = 0.7\n";
  const std::string second = std::string(kScene) + "\n[sky]\nmax_dolp = 0.9\n";
  std::thread([&] { render::render_scene(scene::parse_scene(second, "fresh.toml"), (dir / "fresh.exr").string()); }).join();
  std::thread([&] {
    render::render_scene(scene::parse_scene(first, "first.toml"), (dir / "first.exr").string());
    render::render_scene(scene::parse_scene(second, "fresh.toml"), (dir / "second.exr").string());
  }).join();
  CHECK(file_bytes((dir / "second.exr").string()) == file_bytes((dir / "fresh.exr").string()));
  CHECK(file_bytes((dir / "first.exr").string()) != file_bytes((dir / "fresh.exr").string()));  // the sky did change
  fs::remove_all(dir);
}

TEST_CASE("an uncompressed stack, each part rendered while the last is written, holds a compressed one's frames", "[stack]") {
  // render_scene overlaps rendering and writing only for compression none (render/pipeline.cpp);
  // a zip stack is written part after part. Both must hold the same pixels and truths, part by
  // part, also when the thread's spare frames come from a stack of another size.
  const fs::path dir = temp_dir();
  const std::string base = std::string(kScene) + "[output]\npixel_type = \"float\"\n";
  std::string other = base;
  other.replace(other.find("width = 70\nheight = 60"), 22, "width = 90\nheight = 50");
  std::thread([&] {
    render::render_scene(scene::parse_scene(base + "compression = \"zip\"\n", "zip.toml"), (dir / "zip.exr").string());
    render::render_scene(scene::parse_scene(base + "compression = \"none\"\n", "none.toml"), (dir / "none.exr").string());
    render::render_scene(scene::parse_scene(other + "compression = \"none\"\n", "other.toml"), (dir / "other.exr").string());
    render::render_scene(scene::parse_scene(base + "compression = \"none\"\n", "none.toml"), (dir / "again.exr").string());
  }).join();
  const stack::Stack zip = stack::read_stack((dir / "zip.exr").string());
  for (const char* name : {"none.exr", "again.exr"}) {
    INFO(name);
    const stack::Stack none = stack::read_stack((dir / name).string());
    REQUIRE(none.frames.size() == 3);
    REQUIRE(zip.frames.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(none.frames[i].truth.time.unix_seconds == zip.frames[i].truth.time.unix_seconds);
      CHECK(none.frames[i].channels == zip.frames[i].channels);
    }
    // The frames differ from part to part (the sun moves), so a part in the wrong place would show.
    CHECK(none.frames[0].channel("DoLP.Y") != none.frames[1].channel("DoLP.Y"));
  }
  CHECK(file_bytes((dir / "again.exr").string()) == file_bytes((dir / "none.exr").string()));
  fs::remove_all(dir);
}

TEST_CASE("the overlapped writer fills parts in order, one at a time, into the bytes of the plain writer", "[stack]") {
  const fs::path dir = temp_dir();
  const std::vector<scene::Truth> truths = truths_every_minute(5);
  auto fill = [](std::size_t i, stack::Frame& f) {
    f.width = 4, f.height = 3;
    f.channels["mask"] = std::vector<float>(12, static_cast<float>(i) + 0.5f);
  };
  std::vector<std::size_t> order;
  std::atomic<int> inside{0};
  int most_inside = 0;
  std::array<stack::Frame, 2> frames;
  stack::write_stack_overlapped((dir / "overlapped.exr").string(), truths, {"mask"}, 4, 3, {}, {}, frames,
                                [&](std::size_t i, stack::Frame& f) {
                                  most_inside = std::max(most_inside, ++inside);
                                  order.push_back(i);
                                  fill(i, f);
                                  --inside;
                                });
  CHECK(order == std::vector<std::size_t>{0, 1, 2, 3, 4});
  CHECK(most_inside == 1);
  stack::Frame one;
  stack::write_stack_reusing((dir / "plain.exr").string(), truths, {"mask"}, 4, 3, {}, {}, [&](std::size_t i) -> const stack::Frame& {
    fill(i, one);
    return one;
  });
  CHECK(file_bytes((dir / "overlapped.exr").string()) == file_bytes((dir / "plain.exr").string()));
  fs::remove_all(dir);
}

TEST_CASE("the overlapped writer leaves nothing behind when a part fails to render", "[stack][errors]") {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "broken.exr").string();
  const std::vector<scene::Truth> truths = truths_every_minute(4);
  std::array<stack::Frame, 2> frames;
  try {
    stack::write_stack_overlapped(path, truths, {"mask"}, 4, 3, {}, {}, frames, [](std::size_t i, stack::Frame& f) {
      if (i == 2) throw std::runtime_error("renderer failed on part 2");
      f.width = 4, f.height = 3;
      f.channels["mask"] = std::vector<float>(12, 1.0f);
    });
    FAIL("no error");
  } catch (const scene::SceneError& e) {
    CHECK_THAT(e.what(), Catch::Contains("broken.exr") && Catch::Contains("renderer failed on part 2"));
  }
  CHECK_FALSE(fs::exists(path));
  CHECK(fs::is_empty(dir));  // no temporary either
  fs::remove_all(dir);
}

TEST_CASE("the banded writer fills bands in order, one at a time, into the bytes of the plain writer", "[stack]") {
  const fs::path dir = temp_dir();
  const std::vector<scene::Truth> truths = truths_every_minute(3);
  const int w = 5, h = 7;
  // Each pixel's value names its part, row and column, so a band in the wrong place would show.
  auto value = [&](std::size_t i, int y, int x) { return static_cast<float>(i) * 100 + static_cast<float>(y) + 0.01f * static_cast<float>(x); };
  // Rows y0..y1 of part i into f, as the banded writer asks for a band and the plain one for a frame.
  auto paint = [&](std::size_t i, int y0, int y1, stack::Frame& f) {
    f.width = w, f.height = y1 - y0;
    for (const char* c : {"DoLP.Y", "mask"}) {
      std::vector<float>& v = f.channels[c];
      v.resize(static_cast<std::size_t>(w * (y1 - y0)));
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < w; ++x) v[static_cast<std::size_t>((y - y0) * w + x)] = value(i, y, x);
    }
  };
  for (bool half : {false, true}) {
    for (int band_rows : {1, 3, 7, 50}) {  // bands that divide the height, that do not, one for all
      INFO("half " << half << ", band_rows " << band_rows);
      stack::WriteOptions o;
      o.compression = "none";
      o.half = half;
      std::vector<std::tuple<std::size_t, int, int>> order;
      std::atomic<int> inside{0};
      int most_inside = 0;
      std::array<stack::Frame, 2> bands;
      stack::write_stack_banded((dir / "banded.exr").string(), truths, {"DoLP.Y", "mask"}, w, h, {}, o, band_rows, bands,
                                [&](std::size_t i, int y0, int y1, stack::Frame& f) {
                                  most_inside = std::max(most_inside, ++inside);
                                  order.emplace_back(i, y0, y1);
                                  paint(i, y0, y1, f);
                                  --inside;
                                });
      std::vector<std::tuple<std::size_t, int, int>> expected;
      for (std::size_t i = 0; i < truths.size(); ++i)
        for (int y0 = 0; y0 < h; y0 += band_rows) expected.emplace_back(i, y0, std::min(h, y0 + band_rows));
      CHECK(order == expected);
      CHECK(most_inside == 1);
      stack::Frame one;
      stack::write_stack_reusing((dir / "plain.exr").string(), truths, {"DoLP.Y", "mask"}, w, h, {}, o,
                                 [&](std::size_t i) -> const stack::Frame& {
                                   paint(i, 0, h, one);
                                   return one;
                                 });
      CHECK(file_bytes((dir / "banded.exr").string()) == file_bytes((dir / "plain.exr").string()));
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("the banded writer leaves nothing behind when a band fails to render", "[stack][errors]") {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "broken.exr").string();
  const std::vector<scene::Truth> truths = truths_every_minute(3);
  stack::WriteOptions o;
  o.compression = "none";
  for (int failing : {0, 1, 5}) {  // the first band (on this thread), the second (on the filler), a later one
    INFO("failing band " << failing);
    std::array<stack::Frame, 2> bands;
    int band = 0;
    try {
      stack::write_stack_banded(path, truths, {"mask"}, 4, 3, {}, o, 2, bands, [&](std::size_t, int y0, int y1, stack::Frame& f) {
        if (band++ == failing) throw std::runtime_error("renderer failed on a band");
        f.width = 4, f.height = y1 - y0;
        f.channels["mask"] = std::vector<float>(static_cast<std::size_t>(4 * (y1 - y0)), 1.0f);
      });
      FAIL("no error");
    } catch (const scene::SceneError& e) {
      CHECK_THAT(e.what(), Catch::Contains("broken.exr") && Catch::Contains("renderer failed on a band"));
    }
    CHECK_FALSE(fs::exists(path));
    CHECK(fs::is_empty(dir));  // no temporary either
  }
  fs::remove_all(dir);
}
