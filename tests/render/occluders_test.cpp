// Occluders against independent geometry: boxes against a slab test in double precision written
// here, OBJ meshes against the box they describe, the horizon against its own interpolation rule;
// the renderer's mask against the same tests per pixel; the shaded rule's closed form; a scene
// without occluders creates no Embree device; every class of bad [occluders] input is an error
// that names the file, line and key; the two occluder scenes render without NaN or Inf.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include "camera/orientation.h"
#include "camera/radial_lens.h"
#include "render/horizon_mesh.h"
#include "render/occluder_geometry.h"
#include "render/occluders_embree.h"
#include "render/pipeline.h"
#include "render/renderer.h"
#include "sky/units.h"
#include "stack/stack_io.h"
#include "sky/rayleigh.h"
#include "sky/sky_test_util.h"

using namespace skypol;
using skypol::testing::sun_at;
using scene::BoxSpec;
using scene::OccluderSpec;

namespace {

std::string source(const std::string& rel) { return std::string(SKYPOL_SOURCE_DIR) + "/" + rel; }

std::filesystem::path temp_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("skypol-occluders-test-" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// Uniform unit directions (Marsaglia), deterministic.
std::vector<Eigen::Vector3f> random_directions(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3f> d;
  while (d.size() < n) {
    const double a = u(rng), b = u(rng), s = a * a + b * b;
    if (s >= 1) continue;
    const double r = 2 * std::sqrt(1 - s);
    d.push_back(Eigen::Vector3d(a * r, b * r, 1 - 2 * s).cast<float>());
  }
  return d;
}

// The independent test: does the ray from `eye` along d meet the box grown by `pad` metres on
// every side (pad < 0 shrinks it)? Slabs in the box's own frame, in double precision. The box's
// width axis is East turned clockwise (seen from above) by the yaw: (cos y, −sin y, 0).
bool ray_meets_box(const BoxSpec& b, const Eigen::Vector3d& eye, const Eigen::Vector3d& d, double pad) {
  const double y = rad_from_deg(b.yaw_deg);
  const Eigen::Vector3d ax(std::cos(y), -std::sin(y), 0), ay(std::sin(y), std::cos(y), 0), az(0, 0, 1);
  const Eigen::Vector3d o = eye - b.position_m;
  const double lo[3] = {-b.size_m.x() / 2 - pad, -b.size_m.y() / 2 - pad, -pad};
  const double hi[3] = {b.size_m.x() / 2 + pad, b.size_m.y() / 2 + pad, b.size_m.z() + pad};
  const Eigen::Vector3d axes[3] = {ax, ay, az};
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double ok = o.dot(axes[k]), dk = d.dot(axes[k]);
    if (std::abs(dk) < 1e-300) {
      if (ok < lo[k] || ok > hi[k]) return false;
      continue;
    }
    double a = (lo[k] - ok) / dk, c = (hi[k] - ok) / dk;
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  return t0 <= t1;
}

// Verdict of the independent test with a margin: 1 hit, 0 miss, −1 too close to an edge to say
// at float precision (the ray passes within `pad` of the surface's boundary).
int box_verdict(const std::vector<BoxSpec>& boxes, const Eigen::Vector3d& eye, const Eigen::Vector3d& d, double pad) {
  bool outer = false, inner = false;
  for (const BoxSpec& b : boxes) {
    outer = outer || ray_meets_box(b, eye, d, pad);
    inner = inner || ray_meets_box(b, eye, d, -pad);
  }
  return inner ? 1 : (outer ? -1 : 0);
}

std::vector<BoxSpec> some_boxes() {
  std::vector<BoxSpec> boxes(4);
  boxes[0] = {Eigen::Vector3d(-15.5, 10, 0), Eigen::Vector3d(15, 20, 30), 0};
  boxes[1] = {Eigen::Vector3d(14, -8, 0), Eigen::Vector3d(12, 25, 18), 23};
  boxes[2] = {Eigen::Vector3d(-3, -20, 0), Eigen::Vector3d(4, 3, 6), -61};
  boxes[3] = {Eigen::Vector3d(30, 40, 5), Eigen::Vector3d(6, 6, 40), 135};  // raised: a gap below it
  return boxes;
}

// An independent reading of the horizon rule: linear in azimuth, wrapping through 360°.
double profile_at(const std::vector<scene::HorizonPoint>& p, double az) {
  if (p.size() == 1) return p[0].elevation_deg;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const scene::HorizonPoint& a = p[i];
    const scene::HorizonPoint& b = p[(i + 1) % p.size()];
    const double b_az = i + 1 < p.size() ? b.azimuth_deg : b.azimuth_deg + 360;
    for (double shift : {0.0, 360.0}) {
      const double x = az + shift;
      if (x >= a.azimuth_deg && x <= b_az) return a.elevation_deg + (x - a.azimuth_deg) / (b_az - a.azimuth_deg) * (b.elevation_deg - a.elevation_deg);
    }
  }
  FAIL("azimuth not covered");
  return 0;
}

std::shared_ptr<const camera::Camera> fisheye(int w, int h, double heading, double tilt) {
  camera::Intrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 0.95 * (h / 2.0) / rad_from_deg(92.5);
  k.cx = (w - 1) / 2.0;
  k.cy = (h - 1) / 2.0;
  auto lens = std::make_shared<camera::RadialLens>(camera::Mapping::equidistant, k, rad_from_deg(92.5));
  return std::make_shared<camera::Camera>(lens, camera::world_from_heading_tilt_roll(heading, tilt, 0));
}

// A scene file of the repository read with 8×8 binning (306×256 px).
scene::Scene small_scene(const std::string& rel) { return scene::load_scene(source(rel), {{"camera.binning", "8"}}); }

void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

// A unit cube standing on the origin, as an OBJ file, with the up axis `up`.
std::string cube_obj(bool y_up) {
  std::string s = "# unit cube on its base\n";
  for (int k = 0; k < 8; ++k) {
    const double x = k & 1 ? 0.5 : -0.5, y = k & 2 ? 0.5 : -0.5, z = k & 4 ? 1.0 : 0.0;
    // y-up files hold (East, Up, South).
    s += y_up ? "v " + std::to_string(x) + " " + std::to_string(z) + " " + std::to_string(-y) + "\n"
              : "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
  }
  s += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  return s;
}

const char* kSceneHead = R"([site]
latitude_deg = 43.3
longitude_deg = 5.4

[time]
instants = ["2022-09-23T10:00:00Z", "2022-09-23T12:00:00Z"]

[camera]
model = "equidistant"
focal_mm = 1.8
pitch_um = 3.45
width = 2448
height = 2048
binning = 16
fov_deg = 185
)";

std::string error_of(const std::string& text, const std::string& file = "bad.toml") {
  try {
    scene::parse_scene(text, file);
  } catch (const scene::SceneError& e) {
    return e.what();
  }
  return "no error";
}

void check_all_finite(const std::string& stack_path) {
  const stack::Stack stack = stack::read_stack(stack_path);
  for (const stack::Frame& f : stack.frames) {
    for (const auto& [name, values] : f.channels) {
      INFO(stack_path << " channel " << name);
      CHECK(std::count_if(values.begin(), values.end(), [](float v) { return !std::isfinite(v); }) == 0);
    }
  }
}

}  // namespace

TEST_CASE("boxes block exactly the rays an independent slab test says meet them", "[occluders]") {
  OccluderSpec spec;
  spec.boxes = some_boxes();
  spec.observer_height_m = 1.6;
  const auto occ = render::make_occluders(spec);
  const auto dirs = random_directions(200000, 7);
  std::vector<std::uint8_t> hit(dirs.size());
  occ->occluded(dirs, hit);
  const Eigen::Vector3d eye(0, 0, 1.6);
  std::size_t hits = 0, unsure = 0;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    // Float geometry at up to ~60 m: a margin of 1 mm leaves only rays grazing an edge undecided.
    const int v = box_verdict(spec.boxes, eye, dirs[i].cast<double>().normalized(), 1e-3);
    if (v < 0) {
      ++unsure;
      continue;
    }
    hits += v;
    INFO("direction " << dirs[i].transpose());
    REQUIRE(hit[i] == v);
  }
  CHECK(hits > 10000);             // the boxes cover a good part of the sphere
  CHECK(unsure < dirs.size() / 2000);
}

TEST_CASE("the renderer's mask is 0 exactly where the pixel's ray meets a box", "[occluders][renderer]") {
  OccluderSpec spec;
  spec.boxes = some_boxes();
  spec.observer_height_m = 1.6;
  for (double tilt : {0.0, 60.0}) {
    const auto cam = fisheye(120, 100, 25, tilt);
    const render::Renderer r(cam, render::RenderOptions{}, render::make_occluders(spec));
    const stack::Frame f = r.render(sky::RayleighSky(sky::RayleighParams{1.0}), sun_at(120, 35));
    const auto& mask = f.channel("mask");
    const auto& s0 = f.channel("S0.Y");
    int blocked = 0;
    for (int y = 0; y < cam->height(); ++y) {
      for (int x = 0; x < cam->width(); ++x) {
        const std::size_t i = static_cast<std::size_t>(y * cam->width() + x);
        const auto ray = cam->ray(Eigen::Vector2d(x, y));
        if (!ray) {
          REQUIRE(mask[i] == 0.0f);
          continue;
        }
        const int v = box_verdict(spec.boxes, Eigen::Vector3d(0, 0, 1.6), ray->d, 1e-3);
        if (v < 0) continue;
        INFO("tilt " << tilt << " pixel " << x << ", " << y);
        REQUIRE(mask[i] == (v ? 0.0f : 1.0f));
        if (v) {
          ++blocked;
          CHECK(s0[i] == 0.0f);  // masked rule: no light, unpolarized
        }
      }
    }
    CHECK(blocked > 500);
  }
}

TEST_CASE("an OBJ mesh blocks what the box it describes blocks, with its placement and axes", "[occluders][obj]") {
  const auto dir = temp_dir("obj");
  for (bool y_up : {false, true}) {
    write_file(dir / "cube.obj", cube_obj(y_up));
    const std::string scene = std::string(kSceneHead) + R"(
[occluders]
observer_height_m = 2
[[occluders.mesh]]
path = "cube.obj"
position_m = [12, -7, 1]
yaw_deg = 40
scale = 8
up_axis = ")" + (y_up ? "y" : "z") + "\"\n";
    write_file(dir / "scene.toml", scene);
    const scene::Scene s = scene::load_scene((dir / "scene.toml").string());
    REQUIRE(s.occluders.meshes.size() == 1);
    CHECK(s.occluders.meshes[0].triangles.size() == 12);  // six quads, triangulated
    const auto occ = render::make_occluders(s.occluders);
    const std::vector<BoxSpec> as_box{{Eigen::Vector3d(12, -7, 1), Eigen::Vector3d(8, 8, 8), 40}};
    const auto dirs = random_directions(100000, 11);
    std::vector<std::uint8_t> hit(dirs.size());
    occ->occluded(dirs, hit);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      const int v = box_verdict(as_box, Eigen::Vector3d(0, 0, 2), dirs[i].cast<double>().normalized(), 1e-3);
      if (v < 0) continue;
      hits += v;
      INFO("y_up " << y_up << " direction " << dirs[i].transpose());
      REQUIRE(hit[i] == v);
    }
    CHECK(hits > 1000);
  }
}

TEST_CASE("the horizon blocks every direction below its profile and none above", "[occluders][horizon]") {
  using scene::HorizonPoint;
  const std::vector<std::vector<HorizonPoint>> profiles{
      {{10, 5}, {95, 22}, {180, -3}, {200, 40}, {300, 1}},  // wraps from 300° to 10°
      {{0, 0}},                                             // a flat horizon
      {{0, -20}, {120, 60}, {240, 10}},                     // steep and below the horizontal
  };
  for (const auto& profile : profiles) {
    OccluderSpec spec;
    spec.horizon = profile;
    spec.observer_height_m = 3;  // the horizon is centred on the eye whatever its height
    const auto occ = render::make_occluders(spec);
    auto dirs = random_directions(200000, 3);
    dirs.emplace_back(0, 0, -1);  // the nadir: the floor's centre vertex
    dirs.emplace_back(0, 0, 1);
    std::vector<std::uint8_t> hit(dirs.size());
    occ->occluded(dirs, hit);
    std::size_t unsure = 0;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      const Eigen::Vector3d d = dirs[i].cast<double>().normalized();
      const double el = deg_from_rad(std::asin(std::clamp(d.z(), -1.0, 1.0)));
      double az = deg_from_rad(std::atan2(d.x(), d.y()));
      if (az < 0) az += 360;
      const double limit = profile_at(profile, az);
      // The mesh's straight edges stay within 0.0001° of the rule (render/horizon_mesh.h).
      if (std::abs(el - limit) < 1e-3) {
        ++unsure;
        continue;
      }
      INFO("azimuth " << az << " elevation " << el << " profile " << limit);
      REQUIRE(hit[i] == (el < limit ? 1 : 0));
    }
    CHECK(unsure < 100);
    // The library's own reading of the rule agrees with this one.
    for (double az = -30; az < 400; az += 0.7) {
      CHECK(render::horizon_elevation_deg(profile, az) == Approx(profile_at(profile, std::fmod(az + 360, 360.0))).margin(1e-9));
    }
  }
}

TEST_CASE("shaded occluders hold an unpolarized Lambertian surface under a uniform sky", "[occluders][shaded]") {
  // A wall straight to the North (vertical face, n_z = 0) and a low roof seen from above (n_z = 1).
  OccluderSpec spec;
  spec.observer_height_m = 50;
  spec.boxes = {{Eigen::Vector3d(0, 30, 0), Eigen::Vector3d(40, 2, 100), 0},
                {Eigen::Vector3d(0, -30, 0), Eigen::Vector3d(40, 20, 10), 0}};
  spec.occluded_pixels = scene::OccludedPixels::shaded;
  spec.surface_albedo = 0.4;
  const auto occ = render::make_occluders(spec);
  REQUIRE(occ->shaded());
  const std::vector<Eigen::Vector3f> dirs{Eigen::Vector3f(0, 1, 0), Eigen::Vector3f(0, -0.6f, -0.8f),
                                          Eigen::Vector3f(0, 0, 1)};
  std::vector<float> s0(dirs.size());
  occ->surface_s0(dirs, s0);
  CHECK(s0[0] == Approx(0.4 * 0.5).margin(1e-6));  // (1 + 0) / 2
  CHECK(s0[1] == Approx(0.4).margin(1e-6));        // (1 + 1) / 2
  CHECK(s0[2] == 0.0f);                            // the sky

  // Through the renderer, at 1 and at 4 samples per pixel: occluded pixels are unpolarized with
  // mask 0; a pixel wholly on the wall holds exactly the wall's S0.
  for (int spp : {1, 4}) {
    render::RenderOptions o;
    o.spp = spp;
    const auto cam = fisheye(64, 64, 0, 90);  // looking North, horizontally
    const render::Renderer r(cam, o, occ);
    const stack::Frame f = r.render(sky::RayleighSky(sky::RayleighParams{1.0}), sun_at(200, 40));
    const std::size_t centre = static_cast<std::size_t>(32 * 64 + 32);
    CHECK(f.channel("mask")[centre] == 0.0f);
    CHECK(f.channel("S0.Y")[centre] == Approx(0.2).margin(1e-6));
    CHECK(f.channel("DoLP.Y")[centre] == 0.0f);
    CHECK(f.channel("S1.Y")[centre] == 0.0f);
  }
}

TEST_CASE("a scene without occluders creates no Embree device; one with them creates one", "[occluders][pay]") {
  CHECK(render::make_occluders(OccluderSpec{}) == nullptr);
  const auto dir = temp_dir("pay");
  const std::size_t before = render::embree_devices_created();
  render::render_scene(scene::parse_scene(kSceneHead, "plain.toml"), (dir / "plain.exr").string());
  CHECK(render::embree_devices_created() == before);
  const std::string with = std::string(kSceneHead) + "[occluders]\nhorizon = [[0, 10]]\n";
  render::render_scene(scene::parse_scene(with, "with.toml"), (dir / "with.exr").string());
  CHECK(render::embree_devices_created() == before + 1);
}

TEST_CASE("the occluder scenes load, hold what they say, and render without NaN or Inf", "[occluders][scenes]") {
  const scene::Scene urban = small_scene("scenes/urban-canyon.toml");
  const std::size_t triangles = render::triangle_count(render::occluder_meshes(urban.occluders));
  CHECK(triangles >= 10000);
  CHECK(urban.occluders.boxes.size() == 13);
  const scene::Scene mountains = small_scene("scenes/mountain-horizon.toml");
  CHECK(mountains.occluders.occluded_pixels == scene::OccludedPixels::shaded);
  const auto dir = temp_dir("scenes");
  for (const scene::Scene* s : {&urban, &mountains}) {
    scene::Scene one = *s;
    one.times.resize(2);
    one.output.previews = false;
    const std::string out = (dir / "stack.exr").string();
    render::render_scene(one, out);
    check_all_finite(out);
  }
  // The mountain stack's mask is the profile seen through the lens, pixel by pixel.
  scene::Scene one = mountains;
  one.times.resize(1);
  one.output.previews = false;
  const std::string out = (dir / "mountains.exr").string();
  render::render_scene(one, out);
  const stack::Stack stack = stack::read_stack(out);
  const auto& mask = stack.frames[0].channel("mask");
  const auto& s0 = stack.frames[0].channel("S0.Y");
  std::size_t checked = 0;
  for (int y = 0; y < stack.camera->height(); ++y) {
    for (int x = 0; x < stack.camera->width(); ++x) {
      const auto ray = stack.camera->ray(Eigen::Vector2d(x, y));
      if (!ray) continue;
      const double el = deg_from_rad(std::asin(ray->d.z()));
      double az = deg_from_rad(std::atan2(ray->d.x(), ray->d.y()));
      if (az < 0) az += 360;
      const double limit = profile_at(mountains.occluders.horizon, az);
      if (std::abs(el - limit) < 1e-3) continue;
      const std::size_t i = static_cast<std::size_t>(y * stack.camera->width() + x);
      REQUIRE(mask[i] == (el < limit ? 0.0f : 1.0f));
      if (el < limit) REQUIRE(s0[i] > 0.0f);  // shaded: the mountains show
      ++checked;
    }
  }
  CHECK(checked > 10000);
}

TEST_CASE("a relative mesh path resolves against the scene file", "[occluders][obj]") {
  const auto dir = temp_dir("relative");
  std::filesystem::create_directories(dir / "meshes");
  write_file(dir / "meshes" / "cube.obj", cube_obj(false));
  write_file(dir / "scene.toml", std::string(kSceneHead) + "[occluders]\n[[occluders.mesh]]\npath = \"meshes/cube.obj\"\nposition_m = [0, 10, 0]\n");
  const scene::Scene s = scene::load_scene((dir / "scene.toml").string());
  CHECK(s.occluders.meshes.at(0).path == std::filesystem::absolute(dir / "meshes" / "cube.obj").lexically_normal().string());
}

TEST_CASE("bad [occluders] input is an error naming the file, line and key", "[occluders][errors]") {
  const std::string head = kSceneHead;
  const auto head_lines = static_cast<int>(std::count(head.begin(), head.end(), '\n'));
  struct Case {
    std::string occluders;
    std::string expect;
  };
  const auto dir = temp_dir("errors");
  write_file(dir / "empty.obj", "# nothing\nv 0 0 0\n");
  write_file(dir / "nan.obj", "v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string d = dir.string();
  const std::vector<Case> cases{
      {"horizon = [[10, 5], [5, 6]]\n", "occluders.horizon': azimuths must be strictly increasing"},
      {"horizon = [[360, 5]]\n", "outside [0, 360)"},
      {"horizon = [[0, 90]]\n", "outside (-90, 90)"},
      {"horizon = [[0, 5, 1]]\n", "occluders.horizon': expected an array of [2 numbers] rows"},
      {"horizon = []\n", "needs at least one"},
      {"observer_height_m = 2\n", "names no occluders"},
      {"[[occluders.box]]\nsize_m = [1, 1, 1]\n", "occluders.box[0].position_m'"},
      {"[[occluders.box]]\nposition_m = [5, 5, 0]\nsize_m = [1, 1]\n", "occluders.box[0].size_m': needs 3 numbers"},
      {"[[occluders.box]]\nposition_m = [5, 5, 0]\nsize_m = [1, 0, 1]\n", "occluders.box[0].size_m': each number must be in"},
      {"[[occluders.box]]\nposition_m = [0, 0, 0]\nsize_m = [4, 4, 4]\n", "eye is inside this box"},
      {"[[occluders.box]]\nposition_m = [5, 5, 0]\nsize_m = [1, 1, 1]\nyaw_dg = 3\n", "unknown key 'occluders.box[0].yaw_dg' (did you mean 'occluders.box[0].yaw_deg'?)"},
      {"[[occluders.mesh]]\npath = \"" + d + "/missing.obj\"\n", "occluders.mesh[0].path': no such file"},
      {"[[occluders.mesh]]\npath = \"" + d + "/empty.obj\"\n", "has no faces"},
      {"[[occluders.mesh]]\npath = \"" + d + "/nan.obj\"\n", "is not finite"},
      {"[[occluders.mesh]]\npath = \"" + d + "/empty.obj\"\nup_axis = \"x\"\n", "occluders.mesh[0].up_axis'"},
      {"horizon = [[0, 5]]\noccluded_pixels = \"grey\"\n", "'masked', 'shaded'"},
      {"horizon = [[0, 5]]\nsurface_albedo = 2\noccluded_pixels = \"shaded\"\n", "occluders.surface_albedo'"},
      {"horizon = [[0, 5]]\nbox = 3\n", "expected an array of tables"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(head + "\n[occluders]\n" + c.occluders);
    INFO(c.occluders << "\n→ " << e);
    // file:line:col first, the line inside the [occluders] section (which starts after the head).
    REQUIRE(e.rfind("bad.toml:", 0) == 0);
    CHECK(std::stoi(e.substr(9)) > head_lines);
    CHECK(e.find(c.expect) != std::string::npos);
  }
  // [output] previews is a boolean.
  CHECK(error_of(head + "[output]\npreviews = \"yes\"\n").find("output.previews") != std::string::npos);
}

TEST_CASE("hard cases with occluders: every value finite, the nadir blocked, the zenith free", "[occluders][hard]") {
  OccluderSpec spec;
  spec.horizon = {{0, -5}, {90, 30}, {180, 0}, {270, 85}};
  spec.boxes = {{Eigen::Vector3d(0, 8, 0), Eigen::Vector3d(4, 4, 30), 45}};
  spec.observer_height_m = 1.6;
  for (auto rule : {scene::OccludedPixels::masked, scene::OccludedPixels::shaded}) {
    spec.occluded_pixels = rule;
    const auto occ = render::make_occluders(spec);
    for (double tilt : {0.0, 90.0, 180.0}) {  // zenith, level, nadir: the floor's centre vertex
      for (int spp : {1, 3}) {
        render::RenderOptions o;
        o.spp = spp;
        o.channels = {"S0", "S1", "S2", "S3", "DoLP", "AoLP", "mask"};
        const auto cam = fisheye(40, 40, 0, tilt);
        const render::Renderer r(cam, o, occ);
        for (const sky::Sun& sun : {sun_at(0, 90), sun_at(10, -10), sun_at(300, 0)}) {
          const stack::Frame f = r.render(sky::RayleighSky(sky::RayleighParams{1.0}), sun);
          for (const auto& [name, values] : f.channels) {
            for (float v : values) REQUIRE(std::isfinite(v));
          }
          const float centre = f.channel("mask")[static_cast<std::size_t>(20 * 40 + 20)];
          if (tilt == 180.0) CHECK(centre == 0.0f);  // looking straight down: the floor
          if (tilt == 0.0) CHECK(centre == 1.0f);    // straight up: the sky
        }
      }
    }
  }
}

TEST_CASE("the hard-case scenes with occluders added: no NaN or Inf in any file", "[occluders][hard][scenes]") {
  const auto dir = temp_dir("hard-scenes");
  std::size_t rendered = 0;
  for (const auto& e : std::filesystem::directory_iterator(source("scenes"))) {
    const std::string name = e.path().filename().string();
    if (name.rfind("hard-", 0) != 0 || e.path().extension() != ".toml") continue;
    for (const char* rule : {"masked", "shaded"}) {
      const scene::Scene s = scene::load_scene(
          e.path().string(), {{"camera.binning", "16"},
                              {"occluders.horizon", "[[0, -2], [90, 25], [200, 3], [300, 60]]"},
                              {"occluders.box", "[{position_m = [3, 9, 0], size_m = [4, 6, 30], yaw_deg = 20}]"},
                              {"occluders.observer_height_m", "1.6"},
                              {"occluders.occluded_pixels", rule}});
      REQUIRE(!s.occluders.empty());
      const std::string out = (dir / (e.path().stem().string() + "-" + rule + ".exr")).string();
      render::render_scene(s, out);
      INFO(name << " " << rule);
      check_all_finite(out);
      ++rendered;
    }
  }
  CHECK(rendered >= 10);
}
