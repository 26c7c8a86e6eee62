// classic on a stack read part by part (classic_stream.h): the answer of run_method on the stack
// read whole, bit for bit, and a memory that does not grow with the number of frames. The memory is
// measured through the process's own allocations (this binary replaces operator new and delete to
// count the bytes live), not through time.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>

#include "render/pipeline.h"
#include "scene/scene.h"
#include "stack/stack_io.h"
#include "skypole/classic_stream.h"
#include "skypole/evaluate.h"
#include "skypole/report.h"

namespace {

// Bytes live on the heap (through operator new) and the most since reset_peak().
std::atomic<long long> live{0}, peak{0};

void note(long long delta) {
  const long long now = live.fetch_add(delta, std::memory_order_relaxed) + delta;
  long long p = peak.load(std::memory_order_relaxed);
  while (now > p && !peak.compare_exchange_weak(p, now, std::memory_order_relaxed)) {
  }
}

void reset_peak() { peak.store(live.load()); }

// Each block carries its size in front (16 bytes, keeping new's alignment).
constexpr std::size_t kHead = 16;

void* counted_new(std::size_t n) {
  void* p = std::malloc(n + kHead);
  if (!p) throw std::bad_alloc();
  *static_cast<std::size_t*>(p) = n;
  note(static_cast<long long>(n));
  return static_cast<char*>(p) + kHead;
}

void counted_delete(void* p) noexcept {
  if (!p) return;
  void* block = static_cast<char*>(p) - kHead;
  note(-static_cast<long long>(*static_cast<std::size_t*>(block)));
  std::free(block);
}

}  // namespace

void* operator new(std::size_t n) { return counted_new(n); }
void* operator new[](std::size_t n) { return counted_new(n); }
void operator delete(void* p) noexcept { counted_delete(p); }
void operator delete[](void* p) noexcept { counted_delete(p); }
void operator delete(void* p, std::size_t) noexcept { counted_delete(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_delete(p); }

using namespace skypol;

namespace {

// The paper's day at 128×128 (the image circle of 185° touching the borders), 08:00 UTC every
// `step_min` minutes until `end`, with the channels a render writes by default; `extra`: more
// sections (clouds, a sensor).
std::string scene_text(double step_min, const std::string& end, const std::string& extra = "") {
  return R"(
[site]
latitude_deg = 43.28699
longitude_deg = 5.40336
height_m = 60

[time]
start = "2022-09-23T08:00:00Z"
end = ")" + end + R"("
step_min = )" + std::to_string(step_min) + R"(

[camera]
model = "equidistant"
focal_mm = 0.1367575
pitch_um = 3.45
width = 128
height = 128
fov_deg = 185
heading_deg = 37
tilt_deg = 0

[sky]
model = "rayleigh"
max_dolp = 0.8
)" + extra + R"(

[output]
path = "unused.exr"
channels = ["S0", "S1", "S2", "DoLP", "AoLP", "mask"]
)";
}

std::filesystem::path test_dir() {
  const auto dir = std::filesystem::temp_directory_path() / "skypole_classic_stream_test";
  std::filesystem::create_directories(dir);
  return dir;
}

std::string render_stack(const std::string& text, const std::string& name) {
  const std::string path = (test_dir() / name).string();
  render::render_scene(scene::parse_scene(text, name + ".toml"), path);
  return path;
}

void check_same(const skypole::PoleEstimate& a, const skypole::PoleEstimate& b) {
  CHECK(a.valid == b.valid);
  CHECK(a.why_invalid == b.why_invalid);
  CHECK(a.note == b.note);
  CHECK(a.pole_camera == b.pole_camera);
  CHECK(a.is_north == b.is_north);
  CHECK(a.residual_deg == b.residual_deg);
  CHECK(a.model_misfit == b.model_misfit);
  CHECK(a.sigma_bearing_deg == b.sigma_bearing_deg);
  CHECK(a.sigma_latitude_deg == b.sigma_latitude_deg);
  CHECK(a.cone95_deg == b.cone95_deg);
  CHECK(a.jackknife_frames_rad2 == b.jackknife_frames_rad2);
  CHECK(a.jackknife_frame_groups == b.jackknife_frame_groups);
}

}  // namespace

TEST_CASE("classic streamed from the file is run_method's classic on the stack read whole, bit for bit",
          "[skypole][classic][stream]") {
  // A clear day; a cloudy one (the sky mask at work; the ring-anisotropy gate declines it); one
  // through a sensor (noise); a short window, which classic itself declines; the cloudy day without
  // the sky mask (the misfit gate declines it); a sensor whose polarizers are off their angles (the
  // sky mask's sun fits model them, skypole/sun_vector.h).
  struct Case {
    std::string name, text;
    skypole::InputOptions input;
  };
  skypole::InputOptions no_mask;
  no_mask.sky_mask = false;
  const std::string cloudy = "[sky.clouds]\ncoverage = 0.2\nseed = 3\n";
  const std::string sensor = "[sensor]\npreset = \"sony_imx250mzr\"\n";
  const Case cases[] = {
      {"clear", scene_text(30, "2022-09-23T16:00:00Z"), {}},
      {"cloudy", scene_text(30, "2022-09-23T16:00:00Z", cloudy), {}},
      {"sensor", scene_text(20, "2022-09-23T16:00:00Z", sensor), {}},
      {"short", scene_text(10, "2022-09-23T09:00:00Z"), {}},
      {"unmasked", scene_text(30, "2022-09-23T16:00:00Z", cloudy), no_mask},
      {"polarizers", scene_text(20, "2022-09-23T16:00:00Z", sensor + "angle_error_deg = [1.5, 0.8, -0.3, 1.1]\n"), {}},
  };
  int valid = 0;
  for (const Case& c : cases) {
    INFO(c.name);
    const std::string path = render_stack(c.text, c.name + ".exr");
    const skypole::StreamedEstimate s = skypole::run_classic_streamed(path, c.input);
    const stack::Stack whole = stack::read_stack(path, skypole::estimator_channels(path, c.input));
    const skypole::PoleEstimate e = skypole::run_method(whole, "classic", c.input);
    std::cout << c.name << ": " << (e.valid ? "valid" : "declined: " + e.why_invalid) << "\n";
    check_same(s.estimate, e);
    valid += e.valid ? 1 : 0;
    REQUIRE(s.stack.frames.size() == whole.frames.size());
    CHECK(s.stack.frames.back().truth.time.unix_seconds == whole.frames.back().truth.time.unix_seconds);
    CHECK(s.stack.frames.back().channels.empty());
    // A third pass, for the misfit on the masked sky, only when the mask leaves out sky (the
    // clouds'); else the misfit is that of pass 2's fits on the sky unmasked.
    std::cout << c.name << ": " << s.passes << " passes\n";
    CHECK(s.passes == (c.name == "cloudy" ? 3 : 2));
  }
  CHECK(valid >= 2);  // the comparison covers answers, not only declines
  std::filesystem::remove_all(test_dir());
}

TEST_CASE("classic streamed keeps the same memory for 6, 12 and 24 frames", "[skypole][classic][stream]") {
  // The same day every 80, 40 and 20 minutes. Streamed, the heap's peak holds a few frames and the
  // per-pixel counts; the stack read whole holds every frame's DoLP, AoLP, S0 and mask.
  struct Sweep {
    int frames;
    double step;
    std::string end;
  };
  const Sweep sweep[] = {{6, 80, "2022-09-23T14:40:00Z"}, {12, 40, "2022-09-23T15:20:00Z"}, {24, 20, "2022-09-23T15:40:00Z"}};
  long long streamed_peak[3] = {}, whole_peak[3] = {};
  std::size_t retained[3] = {};
  for (int i = 0; i < 3; ++i) {
    const std::string path = render_stack(scene_text(sweep[i].step, sweep[i].end), "day" + std::to_string(i) + ".exr");
    REQUIRE(stack::peek_stack(path).frames == sweep[i].frames);
    const long long base = live.load();
    reset_peak();
    const skypole::StreamedEstimate s = skypole::run_classic_streamed(path);
    streamed_peak[i] = peak.load() - base;
    retained[i] = s.retained_bytes;
    INFO(s.estimate.why_invalid);
    CHECK(s.estimate.valid);
    const long long base2 = live.load();
    reset_peak();
    {
      const stack::Stack whole = stack::read_stack(path, skypole::estimator_channels(path));
      whole_peak[i] = peak.load() - base2;
    }
  }
  const long long frame_bytes = 128LL * 128 * 4;  // one float image
  for (int i = 0; i < 3; ++i)
    std::cout << "frames " << sweep[i].frames << ": streamed peak " << streamed_peak[i] << " B, retained "
              << retained[i] << " B; the stack read whole " << whole_peak[i] << " B\n";
  // The stack read whole grows by four images a frame: the counter sees the frames.
  CHECK(whole_peak[2] - whole_peak[0] > 18 * 4 * frame_bytes * 9 / 10);
  // Streamed: the peak grows by less than half an image a frame (what grows is OpenEXR's headers of
  // the parts, some 30 kB each whatever the image size), and what the method keeps from frame to
  // frame by less than 1/16 of an image a frame (its per-frame readings, not images).
  CHECK(streamed_peak[2] - streamed_peak[0] < 18 * frame_bytes / 2);
  CHECK(streamed_peak[2] < streamed_peak[0] * 5 / 4);
  CHECK(static_cast<long long>(retained[2]) - static_cast<long long>(retained[0]) < 18 * frame_bytes / 16);
  CHECK(static_cast<long long>(retained[1]) - static_cast<long long>(retained[0]) < 6 * frame_bytes / 16);
  std::filesystem::remove_all(test_dir());
}
