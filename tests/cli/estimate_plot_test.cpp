// `skypol estimate --plot` as a user sees it: the PNG is read back and the marks are found by their
// colour where the answers, the truth, the sun and the cone put them.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "cli/cli_harness.h"
#include "sky/units.h"
#include "stack/oiio_module.h"
#include "stack/preview.h"
#include "stack/stack_io.h"
#include "skypole/estimate_plot.h"
#include "skypole/evaluate.h"
#include "skypole/report.h"

using namespace skypol;
using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

// Marseille in the morning, a zenith camera turned to 30°: the NCP images at 43° altitude.
const std::string kScene = std::string(skypol::test::kMarseilleSite) + R"(
[time]
start = "2022-09-23T07:00:00Z"
end = "2022-09-23T10:00:00Z"
step_min = 30

[camera]
lens_preset = "fujinon_fe185c057ha1"
sensor_preset = "sony_imx250mzr"
binning = 16
heading_deg = 30
)";

struct Png {
  int width = 0, height = 0;
  std::vector<std::array<int, 3>> px;  // 8-bit RGB
  const std::array<int, 3>& at(int x, int y) const { return px[static_cast<std::size_t>(y * width + x)]; }
};

Png read_png(const std::string& path) {
  std::string error;
  auto in = stack::oiio::open(path, &error);
  INFO(path << ": " << error);
  REQUIRE(in);
  Png p;
  p.width = in->width();
  p.height = in->height();
  REQUIRE(in->nchannels() == 3);
  std::vector<float> f(static_cast<std::size_t>(p.width * p.height * 3));
  REQUIRE(in->read(0, f.data()));
  for (std::size_t i = 0; i < f.size(); i += 3) {
    p.px.push_back({static_cast<int>(std::lround(f[i] * 255)), static_cast<int>(std::lround(f[i + 1] * 255)),
                    static_cast<int>(std::lround(f[i + 2] * 255))});
  }
  return p;
}

std::array<int, 3> bytes(const stack::Rgb& c) {
  return {static_cast<int>(std::lround(c[0] * 255)), static_cast<int>(std::lround(c[1] * 255)),
          static_cast<int>(std::lround(c[2] * 255))};
}

bool same(const std::array<int, 3>& a, const std::array<int, 3>& b) {
  return std::abs(a[0] - b[0]) <= 1 && std::abs(a[1] - b[1]) <= 1 && std::abs(a[2] - b[2]) <= 1;
}

// The pixels of `colour` in panel `panel`, in panel coordinates.
std::vector<Eigen::Vector2d> find(const Png& png, const stack::PreviewLayout& l, int panel, const stack::Rgb& colour) {
  std::vector<Eigen::Vector2d> out;
  const auto want = bytes(colour);
  for (int y = 0; y < l.panel_h; ++y) {
    for (int x = 0; x < l.panel_w; ++x) {
      if (same(png.at(l.panel_x[panel] + x, l.panel_y + y), want)) out.emplace_back(x, y);
    }
  }
  return out;
}

Eigen::Vector2d centroid(const std::vector<Eigen::Vector2d>& v) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : v) c += p;
  return c / static_cast<double>(v.size());
}

// Where the picture shows frame pixel (u, v) of a frame sampled every `step` pixels, worked out here
// from the sampling rule (panel pixel k shows frame pixel k·step + step/2).
Eigen::Vector2d expected_panel_pixel(const Eigen::Vector2d& frame_px, int step) {
  return (frame_px - Eigen::Vector2d::Constant(step / 2)) / step;
}

}  // namespace

TEST_CASE("estimate --plot marks each answer's pole, the truth and the sun where they image", "[cli][plot]") {
  TempDir dir;
  const std::string scene = dir.write("marseille.toml", kScene);
  const std::string path = (dir.path / "m.exr").string();
  const Result r = run("render -q " + scene + " -o " + path);
  INFO(r.out);
  REQUIRE(r.code == 0);

  // The same answers in process as the command gives (the same channels read, the same defaults).
  const stack::Stack st = stack::read_stack(path, skypole::estimator_channels(path));
  const skypole::PoleEstimate sv = skypole::run_method(st, "sun_vector");
  REQUIRE(sv.valid);
  REQUIRE(sv.pixel);
  const scene::Truth& truth = st.frames.front().truth;
  REQUIRE(truth.pole_pixel);

  const std::string folder = (dir.path / "plots").string() + "/";
  const Result est = run("estimate -q " + path + " -m sun_vector,great_circle --plot " + folder);
  INFO(est.out);
  REQUIRE(est.code == 0);
  CHECK_THAT(est.out, Catch::Contains("plot     " + folder + "sun_vector.png"));
  REQUIRE(fs::exists(folder + "great_circle.png"));

  const Png png = read_png(folder + "sun_vector.png");
  const stack::PreviewLayout l = stack::plot_layout(st.frames[0].width, st.frames[0].height);
  REQUIRE(png.width == l.width);
  REQUIRE(png.height > l.bar_y);
  for (int panel = 0; panel < 3; ++panel) {
    INFO("panel " << panel);
    // The × in sun_vector's colour, centred on the pixel the estimate names.
    const auto cross = find(png, l, panel, skypole::plot_colour("sun_vector"));
    REQUIRE(cross.size() >= 10);
    CHECK((centroid(cross) - expected_panel_pixel(*sv.pixel, l.step)).norm() < 1.0);
    // The truth's white + on the truth's pixel.
    const auto plus = find(png, l, panel, skypole::kPlotTruthColour);
    REQUIRE(plus.size() >= 10);
    CHECK((centroid(plus) - expected_panel_pixel(*truth.pole_pixel, l.step)).norm() < 1.0);
    // Nothing in great_circle's colour on sun_vector's picture.
    CHECK(find(png, l, panel, skypole::plot_colour("great_circle")).empty());
  }
  // The middle frame's sun (the amber dot the sky mask judged it by) lies where the ephemeris puts it.
  const stack::Frame& middle = st.frames[st.frames.size() / 2];
  const auto sun_px = st.camera->lens().project(middle.truth.world_from_camera.transpose() * middle.truth.sun.direction);
  REQUIRE(sun_px);
  const auto amber = find(png, l, 0, {1.0f, 0.75f, 0.0f});
  REQUIRE(!amber.empty());
  double nearest = 1e9;
  for (const auto& a : amber) nearest = std::min(nearest, (a - expected_panel_pixel(*sun_px, l.step)).norm());
  CHECK(nearest < 2.0);

  // One picture for all: both crosses; the JSON on stdout stays JSON.
  const Result both = run("estimate -q " + path + " -m sun_vector,great_circle --json --plot " + (dir.path / "all.png").string());
  REQUIRE(both.code == 0);
  CHECK(both.out.front() == '[');
  const Png all = read_png((dir.path / "all.png").string());
  CHECK(!find(all, l, 0, skypole::plot_colour("great_circle")).empty());
  CHECK(!find(all, l, 0, skypole::plot_colour("sun_vector")).empty());

  // Every method declines (a bound no cone meets): the picture is still written, with the truth and
  // without any cross, and the command fails as before.
  const std::string declined = (dir.path / "declined.png").string();
  const Result none = run("estimate -q " + path + " -m sun_vector --max-uncertainty 1e-9 --plot " + declined);
  CHECK(none.code != 0);
  const Png d = read_png(declined);
  CHECK(find(d, l, 0, skypole::plot_colour("sun_vector")).empty());
  CHECK(find(d, l, 0, skypole::kPlotTruthColour).size() >= 10);
}

TEST_CASE("the plot's cone is the circle of the stated radius about the pole, through the lens", "[plot]") {
  TempDir dir;
  const std::string scene = dir.write("marseille.toml", kScene);
  const std::string path = (dir.path / "m.exr").string();
  REQUIRE(run("render -q " + scene + " -o " + path).code == 0);
  const stack::Stack st = stack::read_stack(path, skypole::estimator_channels(path));
  skypole::PoleEstimate e = skypole::run_method(st, "sun_vector");
  REQUIRE(e.valid);
  e.cone95_deg = 20;  // wide enough to be many pixels from the pole
  const std::string out = (dir.path / "cone.png").string();
  skypole::write_estimate_plot(st, {e}, {}, out);
  const Png png = read_png(out);
  const stack::PreviewLayout l = stack::plot_layout(st.frames[0].width, st.frames[0].height);
  REQUIRE(l.step == 1);
  const auto ring = find(png, l, 2, [&] {
    stack::Rgb c = skypole::plot_colour("sun_vector");
    for (float& v : c) v *= skypole::kPlotConeShade;
    return c;
  }());
  REQUIRE(ring.size() > 40);
  // Each ring pixel looks 20° from the pole, to within the angle a pixel spans (~1.5° at binning 16).
  for (const auto& p : ring) {
    const auto ray = st.camera->lens().ray(p);
    REQUIRE(ray);
    const double angle = deg_from_rad(std::acos(std::clamp(ray->normalized().dot(e.pole_camera), -1.0, 1.0)));
    CHECK(std::abs(angle - 20) < 2.0);
  }
}
