// skypol export streams: its memory is a frame's, not the stack's, and a stack it cannot read to
// the end leaves no export behind.
#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/truth.h"
#include "stack/export.h"
#include "stack/npy.h"
#include "stack/stack_io.h"

using namespace skypol;
namespace fs = std::filesystem;

namespace {

// 1224×1024 pixels (5 MB of float per channel), 30 frames.
const char* kScene = R"([site]
latitude_deg = 43.3
longitude_deg = 5.4

[time]
start = "2022-09-23T07:00:00Z"
end = "2022-09-23T09:54:00Z"
step_min = 6

[camera]
lens_preset = "fujinon_fe185c057ha1"
sensor_preset = "sony_imx250mzr"
binning = 2
)";

long peak_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;  // KiB on Linux
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("skypol-export-test-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Frame i's DoLP at pixel k: a value each frame and pixel can be told apart by.
float dolp(std::size_t i, std::size_t k) { return static_cast<float>(i) * 0.01f + static_cast<float>(k % 7) * 1e-4f; }

}  // namespace

TEST_CASE("export holds one frame at a time and leaves nothing of a stack it cannot finish", "[stack][export]") {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "long.exr").string();
  const scene::Scene scene = scene::parse_scene(kScene, "long.toml");
  const auto cam = scene::build_camera(scene.camera);
  const int w = cam->width(), h = cam->height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<scene::Truth> truths;
  for (const sky::Instant t : scene.times) truths.push_back(scene::make_truth(scene, *cam, t));
  REQUIRE(truths.size() == 30);
  stack::StackHeader header;
  header.camera_description = scene.camera.description;
  header.scene_text = kScene;
  header.sky_model = "test";
  stack::WriteOptions wo;
  wo.half = false;
  stack::write_stack(path, truths, {"DoLP.Y"}, w, h, header, wo, [&](std::size_t i) {
    stack::Frame f;
    f.width = w;
    f.height = h;
    std::vector<float>& v = f.channels["DoLP.Y"];
    v.resize(n);
    for (std::size_t k = 0; k < n; ++k) v[k] = dolp(i, k);
    return f;
  });
  const double frame_mib = static_cast<double>(n * sizeof(float)) / (1 << 20);

  stack::ExportOptions o;
  o.format = "npy";
  o.channels = {"DoLP"};
  o.out_dir = (dir / "out").string();
  const long before = peak_rss_kib();
  const std::vector<std::string> files = stack::export_stack(path, o);
  const double grew_mib = static_cast<double>(peak_rss_kib() - before) / 1024;
  REQUIRE(files.size() == 30);
  // The whole stack is 30 frames (143 MiB); holding it would raise the peak by at least that much.
  INFO("peak memory grew " << grew_mib << " MiB; a frame is " << frame_mib << " MiB");
  CHECK(grew_mib < 4 * frame_mib);
  // The values are each frame's own.
  for (const std::size_t i : {std::size_t{0}, std::size_t{17}, std::size_t{29}}) {
    const stack::NpyArray a = stack::read_npy(files[i]);
    REQUIRE(a.shape == std::vector<std::size_t>{static_cast<std::size_t>(h), static_cast<std::size_t>(w)});
    for (const std::size_t k : {std::size_t{0}, std::size_t{12345}, n - 1}) CHECK(a.values[k] == static_cast<double>(dolp(i, k)));
  }

  // The same stack cut short: the frames before the cut were exported, then the read failed; the
  // error names the stack and no file of that export stays.
  const std::string cut = (dir / "cut.exr").string();
  fs::copy_file(path, cut);
  fs::resize_file(cut, fs::file_size(path) * 2 / 3);
  o.out_dir = (dir / "cut").string();
  CHECK_THROWS_WITH(stack::export_stack(cut, o), Catch::Contains("cut.exr"));
  CHECK(fs::is_empty(o.out_dir));
  fs::remove_all(dir);
}
