// Sweeps: the grid (lists, ranges of numbers and of dates, file order, the last axis fastest),
// the variants' scenes and truth, shards that partition the grid, resume, and errors reported at
// the sweep file's entry that caused them.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "scene/json_text.h"
#include "sky/units.h"
#include "stack/stack_io.h"
#include "stack/temp_files.h"
#include "render/sweep_run.h"
#include "scene/sweep.h"

using skypol::rad_from_deg;

namespace fs = std::filesystem;
using namespace skypol::scene;
using namespace skypol::stack;
using namespace skypol::render;

namespace {

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("skypol-sweep-" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

const char* kBase = R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336

[time]
start = "2022-09-23T08:00:00Z"
end = "2022-09-23T14:00:00Z"
step_min = 180

[camera]
model = "equidistant"
focal_mm = 1.8
pitch_um = 55.2
width = 153
height = 128
fov_deg = 185
)";

std::string error_of(const TempDir& d, const std::string& sweep_text) {
  const std::string path = d.write("sweep.toml", sweep_text);
  try {
    const Sweep s = load_sweep(path);
    for (std::size_t i = 0; i < s.size(); ++i) (void)make_variant(s, i);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

}  // namespace

TEST_CASE("a grid is the product of its axes in file order, the last varying fastest", "[sweep]") {
  TempDir d;
  d.write("base.toml", kBase);
  const Sweep s = parse_sweep(R"(base = "base.toml"
[axes]
"site.latitude_deg" = [-30, 0.5, 30]
camera.heading_deg = { start = 0, end = 270, step = 90 }
"time.step_min" = { start = 60, end = 180, count = 3 }
)", (d.path / "sweep.toml").string());
  CHECK(s.base == (d.path / "base.toml").string());
  REQUIRE(s.axes.size() == 3);
  CHECK(s.axes[0].key == "site.latitude_deg");  // the file's order, not toml++'s sorted one
  CHECK(s.axes[1].key == "camera.heading_deg");  // an unquoted dotted key names the same key
  CHECK(s.axes[1].values == std::vector<std::string>{"0", "90", "180", "270"});  // integers stay integers
  CHECK(s.axes[2].values == std::vector<std::string>{"60.0", "120.0", "180.0"});
  CHECK(s.size() == 36);
  const Variant v = make_variant(s, 1 * 12 + 2 * 3 + 1);  // latitude 0.5, heading 180, step 120
  CHECK(v.scene.site.latitude_deg == 0.5);
  CHECK(v.scene.camera.heading_deg == 180);
  CHECK(v.scene.times.size() == 4);  // 08:00 .. 14:00 every 120 min
  CHECK(v.params == std::vector<std::pair<std::string, std::string>>{
                        {"site.latitude_deg", "0.5"}, {"camera.heading_deg", "180"}, {"time.step_min", "120.0"}});
  CHECK(v.truth.heading_deg == 180);
  CHECK(v.truth.pole_is_north);
  // The pole of an observer at latitude φ stands φ above the northern horizon (ENU).
  CHECK(v.truth.pole_enu.z() == Approx(std::sin(rad_from_deg(0.5))).epsilon(1e-12));
  CHECK(v.file.substr(0, 7) == "000019-");
}

TEST_CASE("ranges of floats are rounded to 12 digits; ranges of dates step in days", "[sweep]") {
  TempDir d;
  d.write("base.toml", kBase);
  const Sweep s = parse_sweep(R"(base = "base.toml"
[axes]
"sky.max_dolp" = { start = 0.1, end = 0.5, step = 0.1 }
"time.dates" = { start = "2022-02-27", end = 2022-03-02, step_days = 2 }
[set]
time = { zone = "Z", times_of_day = ["08:00", "12:00"] }
)", (d.path / "sweep.toml").string());
  CHECK(s.axes[0].values == std::vector<std::string>{"0.1", "0.2", "0.3", "0.4", "0.5"});
  CHECK(s.axes[1].values == std::vector<std::string>{"\"2022-02-27\"", "\"2022-03-01\""});  // across the month end
}

TEST_CASE("shards partition the grid: every variant in exactly one", "[sweep]") {
  for (std::size_t n : {1u, 3u, 7u}) {
    std::vector<int> owners(20, 0);
    for (std::size_t i = 1; i <= n; ++i) {
      const Shard s = parse_shard(std::to_string(i) + "/" + std::to_string(n));
      for (std::size_t k = 0; k < owners.size(); ++k) owners[k] += s.has(k) ? 1 : 0;
    }
    CHECK(std::all_of(owners.begin(), owners.end(), [](int o) { return o == 1; }));
  }
  for (const char* bad : {"0/4", "5/4", "1/0", "4", "a/b", "-1/4", "1/4/2", " 1/4"}) {
    INFO(bad);
    CHECK_THROWS_AS(parse_shard(bad), std::invalid_argument);
  }
  CHECK_THROWS_WITH(parse_shard("5/4"), Catch::Contains("shard 5 is outside 1..4"));
}

TEST_CASE("a run writes the manifest and one stack per variant; a second run skips them", "[sweep]") {
  TempDir d;
  d.write("base.toml", kBase);
  const Sweep s = load_sweep(d.write("sweep.toml", R"(base = "base.toml"
[set]
"camera.heading_deg" = 30
[axes]
"site.latitude_deg" = [-20, 45]
"camera.tilt_deg" = [0, 10]
)"));
  SweepOptions o;
  o.out_dir = (d.path / "out").string();
  o.shard = parse_shard("2/3");  // variants 1 (and 4, which does not exist)
  const SweepReport first = run_sweep(s, o);
  CHECK(first.variants == 4);
  CHECK(first.in_shard == 1);
  CHECK(first.rendered == 1);
  // The manifest lists every variant whatever the shard, with its truth.
  const std::vector<std::string> manifest = lines_of(d.path / "out" / "manifest.jsonl");
  REQUIRE(manifest.size() == 4);
  CHECK_THAT(manifest[1], Catch::StartsWith("{\"index\": 1, \"file\": \"000001-"));
  CHECK_THAT(manifest[1], Catch::Contains("\"params\": {\"site.latitude_deg\": -20, \"camera.tilt_deg\": 10}"));
  CHECK_THAT(manifest[1], Catch::Contains("\"latitude_deg\": -20, \"longitude_deg\": 5.40336"));
  CHECK_THAT(manifest[1], Catch::Contains("\"heading_deg\": 30, \"tilt_deg\": 10, \"roll_deg\": 0, \"pole\": \"south\""));
  CHECK_THAT(manifest[1], Catch::Contains("\"frames\": 3, \"first_time\": \"2022-09-23T08:00:00Z\""));
  // Every field of the line against a value computed here: the scene and the sweep give the site,
  // orientation and times; the pole is the south celestial pole at 20 deg elevation; its pixel
  // is where the variant's camera (built from the base scene with the same keys) images it.
  {
    const std::string& m = manifest[1];
    auto field = [&m](const std::string& key) {
      const auto at = m.find("\"" + key + "\": ");
      REQUIRE(at != std::string::npos);
      const auto b = at + key.size() + 4;
      const auto e = m[b] == '[' ? m.find(']', b) + 1 : m.find_first_of(",}", b);
      return m.substr(b, e - b);
    };
    auto numbers = [](std::string t) {
      std::vector<double> v;
      for (char& c : t) if (c == '[' || c == ']' || c == ',') c = ' ';
      std::istringstream is(t);
      for (double x; is >> x;) v.push_back(x);
      return v;
    };
    CHECK(field("index") == "1");
    CHECK(std::stod(field("latitude_deg")) == -20);
    CHECK(std::stod(field("longitude_deg")) == 5.40336);
    CHECK(std::stod(field("height_m")) == 0);
    CHECK(std::stod(field("heading_deg")) == 30);
    CHECK(std::stod(field("tilt_deg")) == 10);
    CHECK(std::stod(field("roll_deg")) == 0);
    CHECK(field("pole") == "\"south\"");
    const std::vector<double> pole = numbers(field("pole_enu"));
    REQUIRE(pole.size() == 3);
    const double el = rad_from_deg(20);
    CHECK(pole[0] == Approx(0).margin(1e-9));
    CHECK(pole[1] == Approx(-std::cos(el)).epsilon(1e-9));
    CHECK(pole[2] == Approx(std::sin(el)).epsilon(1e-9));
    const Scene variant_scene = load_scene((d.path / "base.toml").string(),
                                           {Override{"site.latitude_deg", "-20"}, Override{"camera.tilt_deg", "10"},
                                            Override{"camera.heading_deg", "30"}});
    const auto cam = build_camera(variant_scene.camera);
    const std::optional<Eigen::Vector2d> px = cam->project(Eigen::Vector3d(0, -std::cos(el), std::sin(el)));
    REQUIRE(px.has_value());
    const std::vector<double> pixel = numbers(field("pole_pixel"));
    REQUIRE(pixel.size() == 2);
    CHECK(pixel[0] == Approx(px->x()).margin(1e-4));
    CHECK(pixel[1] == Approx(px->y()).margin(1e-4));
    CHECK(field("frames") == "3");
    CHECK(field("first_time") == "\"2022-09-23T08:00:00Z\"");
    CHECK(field("last_time") == "\"2022-09-23T14:00:00Z\"");
    CHECK(field("site.latitude_deg") == "-20");
    CHECK(field("camera.tilt_deg") == "10");
  }
  CHECK_THAT(manifest[2], Catch::Contains("\"pole\": \"north\""));
  // Exactly the shard's stack exists, and it is variant 1: its headers carry that truth.
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(d.path / "out")) files.insert(e.path().filename().string());
  const std::string name = manifest[1].substr(manifest[1].find("\"file\": \"") + 9, 19);
  CHECK(files == std::set<std::string>{"manifest.jsonl", name});
  const Stack stack = read_stack((d.path / "out" / name).string(), {"mask"});
  REQUIRE(stack.frames.size() == 3);
  CHECK(stack.frames[0].truth.site.latitude_deg == -20);
  CHECK(stack.frames[0].truth.tilt_deg == Approx(10).margin(1e-9));
  CHECK(stack.frames[0].truth.heading_deg == Approx(30).margin(1e-9));
  CHECK_THAT(stack.scene_text, Catch::Contains("site.latitude_deg=-20   (axis site.latitude_deg)"));

  // A dry run counts what is done and renders nothing.
  o.dry_run = true;
  o.shard = Shard{};
  const SweepReport dry = run_sweep(s, o);
  CHECK(dry.in_shard == 4);
  CHECK(dry.skipped == 1);
  CHECK(dry.rendered == 0);
  o.dry_run = false;

  // Leftovers of a killed run on this host (NAME.tmp-HOST-PID) are removed when PID is gone; a live
  // writer's stay, and so do another host's and the host-less ones of older runs (no one here can
  // tell whether their writer lives).
  const std::string variant2 = manifest[2].substr(manifest[2].find("\"file\": \"") + 9, 19);
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const std::string here = ".tmp-" + host_name() + "-";
  std::ofstream(d.path / "out" / (variant2 + here + std::to_string(dead))) << "half a stack";
  std::ofstream(d.path / "out" / (variant2 + here + std::to_string(::getppid()))) << "being written";
  std::ofstream(d.path / "out" / (variant2 + ".tmp-other-node-" + std::to_string(dead))) << "another host's";
  std::ofstream(d.path / "out" / (variant2 + ".tmp-" + std::to_string(dead))) << "an older run's";

  // Resume: the finished variant is skipped; the whole sweep completes the rest.
  const auto mtime = fs::last_write_time(d.path / "out" / name);
  o.shard = Shard{};
  const SweepReport second = run_sweep(s, o);
  CHECK(second.skipped == 1);
  CHECK(second.rendered == 3);
  CHECK(fs::last_write_time(d.path / "out" / name) == mtime);
  CHECK(lines_of(d.path / "out" / "manifest.jsonl") == manifest);  // the same bytes from every run
  CHECK_FALSE(fs::exists(d.path / "out" / (variant2 + here + std::to_string(dead))));
  CHECK(fs::exists(d.path / "out" / (variant2 + here + std::to_string(::getppid()))));
  CHECK(fs::exists(d.path / "out" / (variant2 + ".tmp-other-node-" + std::to_string(dead))));
  CHECK(fs::exists(d.path / "out" / (variant2 + ".tmp-" + std::to_string(dead))));
  const SweepReport third = run_sweep(s, o);
  CHECK(third.rendered == 0);
  CHECK(third.skipped == 4);
}

TEST_CASE("a changed variant gets a new file name, so a stale stack is never taken as done", "[sweep]") {
  TempDir d;
  d.write("base.toml", kBase);
  const std::string path = d.write("sweep.toml", "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = [0, 90]\n");
  const Variant a = make_variant(load_sweep(path), 1);
  d.write("sweep.toml", "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = [0, 90]\n[set]\n\"sky.max_dolp\" = 0.7\n");
  const Variant b = make_variant(load_sweep(path), 1);
  CHECK(a.file.substr(0, 7) == b.file.substr(0, 7));
  CHECK(a.file != b.file);
  // The same variant reached through a different spelling of the same values keeps its name.
  d.write("sweep.toml", "base = \"./base.toml\"\n[axes]\ncamera.heading_deg = { start = 0, end = 90, step = 90 }\n");
  CHECK(make_variant(load_sweep(path), 1).file == a.file);
}

TEST_CASE("sweep errors are reported at the sweep file's entry", "[sweep][errors]") {
  TempDir d;
  d.write("base.toml", kBase);
  const std::string sweep = (d.path / "sweep.toml").string();
  // An axis that names no key.
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"camera.heading_dg\" = [0, 90]\n"),
             Catch::StartsWith(sweep + ":3:23: error: unknown key 'camera.heading_dg' (did you mean 'camera.heading_deg'?)"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"camera.heading_dg\" = [0, 90]\n"),
             Catch::EndsWith("(axis 'camera.heading_dg' = 0)"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"sensr.seed\" = [0, 1]\n"), Catch::Contains("unknown key 'sensr'"));
  // A value out of range, in a list or from a range.
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"site.latitude_deg\" = [0, 95]\n"),
             Catch::StartsWith(sweep + ":3:23: error: key 'site.latitude_deg': value 95 out of range [-90, 90]"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"site.latitude_deg\" = { start = 0, end = 100, step = 50 }\n"),
             Catch::Contains("value 100 out of range [-90, 90] (axis 'site.latitude_deg' = 100)"));
  // A wrong type in [set].
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[set]\n\"camera.width\" = \"wide\"\n"),
             Catch::StartsWith(sweep + ":3:18: error: key 'camera.width': expected an integer, found a string"));
  // The sweep file's own keys.
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axis]\n\"camera.heading_deg\" = [0]\n"),
             Catch::StartsWith(sweep + ":2:2: error: unknown key 'axis' (did you mean 'axes'?)"));
  CHECK_THAT(error_of(d, "[axes]\n\"camera.heading_deg\" = [0]\n"), Catch::Contains("missing key 'base'"));
  CHECK_THAT(error_of(d, "base = \"nope.toml\"\n"),
             Catch::StartsWith(sweep + ":1:8: error: key 'base': cannot open the base scene '" +
                               (d.path / "nope.toml").string() + "'"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = 30\n"),
             Catch::StartsWith(sweep + ":3:24: error: axis 'camera.heading_deg': expected a list of values"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = []\n"), Catch::Contains("no values"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = { start = 0, end = 90 }\n"),
             Catch::Contains("give either 'step' or 'count'"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = { start = 0, end = 90, step = -1 }\n"),
             Catch::Contains("key 'axes.camera.heading_deg.step': must be non-zero and go from start towards end"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\n\"camera.heading_deg\" = [0]\n[set]\n\"camera.heading_deg\" = 3\n"),
             Catch::Contains("axis 'camera.heading_deg' is also in [set]"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes]\na = { start = 0, end = 999, step = 1 }\n"
                         "b = { start = 0, end = 999, step = 1 }\n"),
             Catch::Contains("the grid has 1000000 variants, more than 100000"));
  CHECK_THAT(error_of(d, "base = \"base.toml\"\n[axes\n"), Catch::Contains("TOML syntax"));
}

TEST_CASE("a failing sweep writes nothing", "[sweep][errors]") {
  TempDir d;
  d.write("base.toml", kBase);
  // The last variant is bad: the check fails before the folder is even created.
  const Sweep s = load_sweep(d.write("sweep.toml", "base = \"base.toml\"\n[axes]\n\"site.latitude_deg\" = [0, 45, 91]\n"));
  SweepOptions o;
  o.out_dir = (d.path / "out").string();
  CHECK_THROWS_WITH(run_sweep(s, o), Catch::Contains("value 91 out of range"));
  CHECK_FALSE(fs::exists(d.path / "out"));
}

TEST_CASE("JSON strings: quotes, backslashes and control characters escaped, UTF-8 kept", "[sweep]") {
  CHECK(skypol::scene::json_quoted("plain") == "\"plain\"");
  CHECK(skypol::scene::json_quoted("a\"b\\c\n\x01 é") == "\"a\\\"b\\\\c\\u000a\\u0001 é\"");
}
