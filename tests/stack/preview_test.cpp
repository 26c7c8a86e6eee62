// Previews: the colour maps have the properties they are designed for (checked in Oklab, computed
// here from sRGB independently of the generator), the picture shows each pixel's value through
// its map, occluded pixels hatched and the outside of the image circle black, the PNG reads back
// as the picture, and a stack's previews come out one per frame or not at all.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>

#include <OpenImageIO/imageio.h>

#include "stack/colormap.h"
#include "render/pipeline.h"
#include "stack/preview.h"

using namespace skypol;
using stack::Rgb;

namespace {

// sRGB (encoded) → Oklab (Ottosson 2020): decode, linear sRGB → LMS, cube root, → Lab.
Eigen::Vector3d oklab(const Rgb& c) {
  auto lin = [](double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
  const double r = lin(c[0]), g = lin(c[1]), b = lin(c[2]);
  const double l = std::cbrt(0.4122214708 * r + 0.5363325363 * g + 0.0514459929 * b);
  const double m = std::cbrt(0.2119034982 * r + 0.6806995451 * g + 0.1073969566 * b);
  const double s = std::cbrt(0.0883024619 * r + 0.2817188376 * g + 0.6299787005 * b);
  return {0.2104542553 * l + 0.7936177850 * m - 0.0040720468 * s, 1.9779984951 * l - 2.4285922050 * m + 0.4505937099 * s,
          0.0259040371 * l + 0.7827717662 * m - 0.8086757660 * s};
}

std::filesystem::path temp_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("skypol-preview-test-" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// A synthetic 80×60 frame: an image circle of radius 28 px, a DoLP ramp along x, an AoLP ramp
// along y, S0 rising along x, and an occluded block in the lower right.
stack::PreviewFrame synthetic() {
  stack::PreviewFrame f;
  f.width = 80;
  f.height = 60;
  const std::size_t n = 80 * 60;
  f.s0.resize(n), f.dolp.resize(n), f.aolp.resize(n), f.mask.resize(n), f.inside.resize(n);
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 80; ++x) {
      const std::size_t i = static_cast<std::size_t>(y * 80 + x);
      f.inside[i] = std::hypot(x - 39.5, y - 29.5) < 28 ? 1 : 0;
      f.mask[i] = (x > 45 && y > 35) ? 0.0f : 1.0f;
      f.dolp[i] = static_cast<float>(x) / 79;
      f.aolp[i] = static_cast<float>((static_cast<double>(y) / 59 - 0.5) * std::numbers::pi);
      f.s0[i] = 1 + static_cast<float>(x) / 79;
    }
  }
  f.title = "synthetic";
  return f;
}

Rgb pixel(const std::vector<float>& img, const stack::PreviewLayout& l, int x, int y) {
  const std::size_t i = 3 * static_cast<std::size_t>(y * l.width + x);
  return {img[i], img[i + 1], img[i + 2]};
}

}  // namespace

TEST_CASE("the DoLP map's lightness rises evenly and stays in gamut", "[preview][colormap]") {
  double previous = -1;
  std::vector<double> steps;
  for (int k = 0; k <= 256; ++k) {
    const Rgb c = stack::perceptual_colour(k / 256.0);
    for (float v : c) REQUIRE((v >= 0 && v <= 1));
    const double lightness = oklab(c).x();
    if (k > 0) {
      REQUIRE(lightness > previous);
      steps.push_back(lightness - previous);
    }
    previous = lightness;
  }
  CHECK(stack::perceptual_colour(0)[0] == stack::perceptual_colour(-3)[0]);  // clamped
  CHECK(stack::perceptual_colour(std::nan(""))[1] == stack::perceptual_colour(0)[1]);
  // Designed as L = 0.28 + 0.64 t; the sRGB tables and their interpolation keep it within 0.01.
  CHECK(oklab(stack::perceptual_colour(0)).x() == Approx(0.28).margin(0.01));
  CHECK(oklab(stack::perceptual_colour(1)).x() == Approx(0.92).margin(0.01));
  const auto [lo, hi] = std::minmax_element(steps.begin(), steps.end());
  CHECK(*hi < 1.6 * *lo);
}

TEST_CASE("the AoLP map is cyclic, of constant lightness, and turns through every hue evenly", "[preview][colormap]") {
  for (int c = 0; c < 3; ++c) {
    CHECK(stack::cyclic_colour(0)[c] == stack::cyclic_colour(1)[c]);
    CHECK(stack::cyclic_colour(0.3)[c] == Approx(stack::cyclic_colour(-0.7)[c]).margin(1e-6));
  }
  std::vector<double> steps;
  double turned = 0;
  Eigen::Vector3d previous = oklab(stack::cyclic_colour(0));
  for (int k = 1; k <= 360; ++k) {
    const Eigen::Vector3d lab = oklab(stack::cyclic_colour(k / 360.0));
    CHECK(lab.x() == Approx(0.72).margin(0.01));
    steps.push_back((lab - previous).norm());
    // Hue advances in the same sense at every step.
    const double dh = std::remainder(std::atan2(lab.z(), lab.y()) - std::atan2(previous.z(), previous.y()), 2 * std::numbers::pi);
    CHECK(dh > 0);
    turned += dh;
    previous = lab;
  }
  CHECK(turned == Approx(2 * std::numbers::pi).margin(1e-9));
  const auto [lo, hi] = std::minmax_element(steps.begin(), steps.end());
  CHECK(*hi < 1.6 * *lo);
}

TEST_CASE("a preview shows each pixel through its map, occluders hatched, the outside black", "[preview]") {
  const stack::PreviewFrame f = synthetic();
  const stack::PreviewLayout l = stack::preview_layout(f.width, f.height, 512);
  REQUIRE(l.step == 1);
  const std::vector<float> img = stack::preview_pixels(f, l);
  REQUIRE(img.size() == 3 * static_cast<std::size_t>(l.width * l.height));
  const Rgb hatch_a = pixel(img, l, l.panel_x[1] + 52, l.panel_y + 42);
  for (int panel = 0; panel < 3; ++panel) {
    // Outside the circle: black.
    for (float v : pixel(img, l, l.panel_x[panel] + 2, l.panel_y + 2)) CHECK(v == 0.0f);
    // Occluded: one of two colours in stripes, the same in every panel.
    const Rgb a = pixel(img, l, l.panel_x[panel] + 52, l.panel_y + 42);
    const Rgb b = pixel(img, l, l.panel_x[panel] + 54, l.panel_y + 42);
    CHECK(a != b);
    CHECK(a == hatch_a);
  }
  // DoLP and AoLP: the maps' colours of the values at those pixels.
  for (int x : {20, 40, 55}) {
    const int y = 25;
    const std::size_t i = static_cast<std::size_t>(y * f.width + x);
    CHECK(pixel(img, l, l.panel_x[1] + x, l.panel_y + y) == stack::perceptual_colour(f.dolp[i]));
    const Rgb aolp = pixel(img, l, l.panel_x[2] + x, l.panel_y + y);
    const Rgb expect = stack::cyclic_colour(double{f.aolp[i]} / std::numbers::pi + 0.5);
    for (int c = 0; c < 3; ++c) CHECK(aolp[c] == Approx(expect[c]).margin(1e-6));
  }
  // S0: grey, brighter where S0 is larger.
  const Rgb dark = pixel(img, l, l.panel_x[0] + 15, l.panel_y + 29);
  const Rgb bright = pixel(img, l, l.panel_x[0] + 45, l.panel_y + 29);
  CHECK(dark[0] == dark[1]);
  CHECK(dark[1] == dark[2]);
  CHECK(bright[0] > dark[0]);
  // The colour bars: each map from one end to the other.
  CHECK(pixel(img, l, l.panel_x[1], l.bar_y + 1) == stack::perceptual_colour(0));
  CHECK(pixel(img, l, l.panel_x[1] + l.panel_w - 1, l.bar_y + 1) == stack::perceptual_colour(1));
  CHECK(pixel(img, l, l.panel_x[2], l.bar_y + 1) == pixel(img, l, l.panel_x[2] + l.panel_w - 1, l.bar_y + 1));
}

TEST_CASE("a large frame is sampled down to the panel size, nearest pixel", "[preview]") {
  const stack::PreviewLayout l = stack::preview_layout(2448, 2048, 512);
  CHECK(l.step == 5);
  CHECK(l.panel_w == 490);
  CHECK(l.panel_h == 410);
  CHECK(l.panel_x[1] >= l.panel_x[0] + l.panel_w);
  CHECK(l.panel_x[2] >= l.panel_x[1] + l.panel_w);
}

TEST_CASE("the PNG reads back, 8-bit sRGB, as the picture", "[preview][png]") {
  const auto dir = temp_dir("png");
  const stack::PreviewFrame f = synthetic();
  const std::string path = (dir / "p.png").string();
  stack::write_preview_png(f, path, 512);
  const stack::PreviewLayout l = stack::preview_layout(f.width, f.height, 512);
  const std::vector<float> img = stack::preview_pixels(f, l);
  auto in = OIIO::ImageInput::open(path);
  REQUIRE(in);
  const OIIO::ImageSpec& spec = in->spec();
  CHECK(spec.width == l.width);
  CHECK(spec.height == l.height);
  CHECK(spec.nchannels == 3);
  CHECK(spec.format == OIIO::TypeDesc::UINT8);
  std::vector<unsigned char> png(static_cast<std::size_t>(spec.width * spec.height * 3));
  REQUIRE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, png.data()));
  // The panels (where no text is drawn) match the picture to 8-bit rounding.
  for (int panel = 0; panel < 3; ++panel) {
    for (int y = l.panel_y; y < l.panel_y + l.panel_h; y += 3) {
      for (int x = l.panel_x[panel]; x < l.panel_x[panel] + l.panel_w; x += 3) {
        const std::size_t i = 3 * static_cast<std::size_t>(y * l.width + x);
        for (int c = 0; c < 3; ++c) REQUIRE(std::abs(png[i + c] - img[i + c] * 255.0f) <= 0.51f);
      }
    }
  }
  // No temporary file is left next to it.
  CHECK(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()) == 1);
}

TEST_CASE("previews: one PNG per frame when asked for, from the scene or from a stack file; none otherwise", "[preview][pipeline]") {
  const auto dir = temp_dir("stack");
  const std::string scene = R"([site]
latitude_deg = 43.3
longitude_deg = 5.4
[time]
instants = ["2022-09-23T08:00:00Z", "2022-09-23T10:30:00Z", "2022-09-23T13:00:00Z"]
[camera]
model = "equidistant"
focal_mm = 1.8
pitch_um = 3.45
width = 2448
height = 2048
binning = 16
fov_deg = 185
[occluders]
horizon = [[0, 10], [180, 30]]
[output]
channels = ["S0", "DoLP"]
)";
  const std::string stack = (dir / "a.exr").string();
  render::render_scene(scene::parse_scene(scene, "a.toml"), stack);
  CHECK(!std::filesystem::exists(stack::preview_folder_for(stack)));

  render::render_scene(scene::parse_scene(scene + "previews = true\n", "a.toml"), stack);
  const std::string folder = stack::preview_folder_for(stack);
  CHECK(folder == (dir / "a-preview").string());
  const std::vector<std::string> names{"0000-20220923T080000Z.png", "0001-20220923T103000Z.png",
                                       "0002-20220923T130000Z.png"};
  for (const std::string& n : names) CHECK(std::filesystem::exists(std::filesystem::path(folder) / n));
  CHECK(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()) == 2);

  // The stack holds only S0 and DoLP: AoLP cannot be made, so `skypol preview` refuses, naming it,
  // and leaves nothing behind.
  CHECK_THROWS_WITH(stack::write_stack_previews(stack, (dir / "from-file").string()),
                    Catch::Contains("DoLP and AoLP, or S1 and S2"));
  CHECK(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()) == 2);

  // A stack with S0, S1, S2: its previews from the file, one per part.
  render::render_scene(scene::parse_scene(scene.substr(0, scene.find("[output]")) + "[output]\nchannels = [\"S0\", \"S1\", \"S2\"]\n", "b.toml"),
                       (dir / "b.exr").string());
  CHECK(stack::write_stack_previews((dir / "b.exr").string(), (dir / "from-file").string()) == 3);
  for (const std::string& n : names) CHECK(std::filesystem::exists(dir / "from-file" / n));
}

TEST_CASE("a preview folder that is not committed leaves nothing behind", "[preview]") {
  const auto dir = temp_dir("uncommitted");
  {
    stack::PreviewFolder folder((dir / "p").string());
    folder.add("x.png", synthetic());
  }
  CHECK(std::filesystem::is_empty(dir));
}

TEST_CASE("the estimate picture puts a mark on the panel pixel that samples its frame pixel", "[preview][plot]") {
  stack::PlotFrame p;
  p.frame = synthetic();  // 80×60
  const std::size_t n = p.frame.s0.size();
  p.categories = {{{0.5f, 0.5f, 0.5f}, "sky"}, {{0.2f, 0.2f, 0.9f}, "other"}};
  p.category.assign(n, 0);
  p.category[0] = 1;
  const Rgb red{1, 0, 0}, green{0, 1, 0};
  // Frame pixel (47, 31) at step 3 (panels of at most 30 px): panel pixel ((47 − 1) / 3, (31 − 1) / 3).
  p.marks.push_back({Eigen::Vector2d(47, 31), red, stack::PlotMark::Shape::dot, 0});
  p.lines.push_back({{Eigen::Vector2d(10, 40), Eigen::Vector2d(70, 40)}, green});
  p.texts.push_back({"a line long enough to be wrapped, a line long enough to be wrapped, a line long enough", green});
  int height = 0;
  const std::vector<float> img = stack::plot_pixels(p, 30, &height);
  const stack::PreviewLayout l = stack::plot_layout(80, 60, 30);
  REQUIRE(l.step == 3);
  REQUIRE(height > l.bar_y + l.bar_h);
  REQUIRE(img.size() == 3 * static_cast<std::size_t>(l.width * height));
  const Eigen::Vector2i at = stack::plot_panel_pixel(l, Eigen::Vector2d(47, 31));
  CHECK(at == Eigen::Vector2i(15, 10));
  for (int panel = 0; panel < 3; ++panel) {
    CHECK(pixel(img, l, l.panel_x[panel] + 15, l.panel_y + 10) == red);
    // Its neighbours are not the mark (a dot of radius 0 is one pixel).
    CHECK(pixel(img, l, l.panel_x[panel] + 16, l.panel_y + 10) != red);
    // The line along frame row 40 is panel row 13, from panel column 3 to 23.
    for (int x = 3; x <= 23; ++x) CHECK(pixel(img, l, l.panel_x[panel] + x, l.panel_y + 13) == green);
    CHECK(pixel(img, l, l.panel_x[panel] + 2, l.panel_y + 13) != green);
  }
  // The third panel colours pixels by category; the corner (0, 0) is outside the image circle: black.
  CHECK(pixel(img, l, l.panel_x[2] + 13, l.panel_y + 6) == Rgb{0.5f, 0.5f, 0.5f});
  CHECK(pixel(img, l, l.panel_x[2], l.panel_y) == Rgb{0, 0, 0});
  // A category that is not listed is refused, naming the problem.
  p.category[5] = 7;
  CHECK_THROWS_WITH(stack::plot_pixels(p, 30, &height), Catch::Contains("category"));
}
