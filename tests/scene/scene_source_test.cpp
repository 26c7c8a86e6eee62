// Where a scene's TOML comes from: includes (relative, nested, merged key by key, cycles caught),
// --set overrides, and errors that point at the file and line that wrote the offending value,
// whichever file or override that was.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "scene/scene.h"

namespace fs = std::filesystem;
using skypol::scene::load_scene;
using skypol::scene::load_scene_source;
using skypol::scene::Override;
using skypol::scene::parse_override;
using skypol::scene::SceneError;

namespace {

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("skypol-source-" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path / "presets" / "deeper"); }
  ~TempDir() { fs::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

const char* kCamera = R"(# a camera preset
[camera]
model = "equidistant"
focal_mm = 1.8
pitch_um = 3.45
width = 64
height = 48
fov_deg = 185
heading_deg = 10
)";

const char* kSiteTime = R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336

[time]
instants = ["2022-09-23T08:00:00Z", "2022-09-23T12:00:00Z"]
)";

std::string error_of(const std::string& path, const std::vector<Override>& overrides = {}) {
  try {
    load_scene(path, overrides);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("an included file is merged under the including one, key by key", "[scene][include]") {
  TempDir d;
  d.write("presets/camera.toml", kCamera);
  const std::string scene = d.write("scene.toml", std::string("include = \"presets/camera.toml\"\n") + kSiteTime +
                                                      "\n[camera]\nheading_deg = 30\n");
  const auto s = load_scene(scene);
  CHECK(s.camera.heading_deg == 30);                 // the including file wins
  CHECK(s.camera.lens.focal_mm == 1.8);              // the rest of [camera] comes from the preset
  CHECK(s.camera.lens.width == 64);
  CHECK(s.site.latitude_deg == 43.28699);
  CHECK(s.times.size() == 2);
}

TEST_CASE("includes are read in order, nested, relative to the file that names them", "[scene][include]") {
  TempDir d;
  d.write("presets/deeper/lens.toml", kCamera);
  // b.toml includes deeper/lens.toml relative to presets/, then overrides the heading.
  d.write("presets/b.toml", "include = [\"deeper/lens.toml\"]\n[camera]\nheading_deg = 20\nwidth = 32\n");
  d.write("presets/c.toml", "[camera]\nheading_deg = 40\n");
  const std::string scene =
      d.write("scene.toml", std::string("include = [\"presets/b.toml\", \"presets/c.toml\"]\n") + kSiteTime);
  const auto s = load_scene(scene);
  CHECK(s.camera.heading_deg == 40);  // c.toml comes after b.toml
  CHECK(s.camera.lens.width == 32);   // b.toml over deeper/lens.toml
  CHECK(s.camera.lens.height == 48);  // from deeper/lens.toml
  // The provenance text names every file and parses back to the same scene.
  const auto src = load_scene_source(scene);
  CHECK_THAT(src.text, Catch::Contains("include " + (d.path / "presets/b.toml").string()));
  CHECK_THAT(src.text, Catch::Contains("include " + (d.path / "presets/deeper/lens.toml").string()));
  const auto again = skypol::scene::parse_scene(src.text, "again.toml");
  CHECK(again.camera.description == s.camera.description);
  CHECK(again.times == s.times);
  CHECK(again.site.latitude_deg == s.site.latitude_deg);
}

TEST_CASE("a scene without includes or overrides keeps its own text, comments and all", "[scene][include]") {
  TempDir d;
  const std::string text = std::string(kSiteTime) + kCamera;
  const auto src = load_scene_source(d.write("plain.toml", text));
  CHECK(src.text == text);
}

TEST_CASE("an error in an included file is reported in that file, at its line", "[scene][include][errors]") {
  TempDir d;
  std::string camera = kCamera;
  camera.replace(camera.find("fov_deg = 185"), 13, "fov_deg = 400");
  const std::string preset = d.write("presets/camera.toml", camera);
  const std::string scene = d.write("scene.toml", std::string("include = \"presets/camera.toml\"\n") + kSiteTime);
  CHECK_THAT(error_of(scene), Catch::StartsWith(preset + ":8:11: error: key 'camera.fov_deg': value 400 out of range"));

  camera = kCamera;
  camera.replace(camera.find("fov_deg"), 7, "fov_dge");
  d.write("presets/camera.toml", camera);
  CHECK_THAT(error_of(scene), Catch::StartsWith(preset + ":8:1: error: unknown key 'camera.fov_dge'"));
  CHECK_THAT(error_of(scene), Catch::Contains("did you mean 'camera.fov_deg'?"));

  d.write("presets/camera.toml", "[camera\nwidth = 3\n");
  CHECK_THAT(error_of(scene), Catch::StartsWith(preset + ":1:"));
  CHECK_THAT(error_of(scene), Catch::Contains("TOML syntax"));
}

TEST_CASE("a missing included file is an error at the include", "[scene][include][errors]") {
  TempDir d;
  const std::string scene = d.write("scene.toml", std::string(kSiteTime) + "\ninclude = 3\n");
  // include must be top-level: after [time] it is time.include, an unknown key.
  CHECK_THAT(error_of(scene), Catch::Contains("unknown key 'time.include'"));
  d.write("scene.toml", std::string("include = [\"presets/camera.toml\",\n  \"presets/nope.toml\"]\n") + kSiteTime);
  d.write("presets/camera.toml", kCamera);
  CHECK_THAT(error_of(scene),
             Catch::StartsWith(scene + ":2:3: error: key 'include': cannot open included file 'presets/nope.toml' (looked for " +
                               (d.path / "presets/nope.toml").string() + ")"));
  d.write("scene.toml", std::string("include = 3\n") + kSiteTime);
  CHECK_THAT(error_of(scene), Catch::StartsWith(scene + ":1:11: error: key 'include': expected a file name"));
}

TEST_CASE("an include cycle is an error naming the chain", "[scene][include][errors]") {
  TempDir d;
  d.write("presets/a.toml", "include = \"b.toml\"\n");
  const std::string b = d.write("presets/b.toml", "\ninclude = \"a.toml\"\n");
  const std::string scene = d.write("scene.toml", std::string("include = \"presets/a.toml\"\n") + kSiteTime + kCamera);
  CHECK_THAT(error_of(scene), Catch::StartsWith(b + ":2:11: error: key 'include': include cycle: scene.toml -> a.toml -> b.toml -> a.toml"));
  // A file included twice by different routes (a diamond) is not a cycle.
  d.write("presets/a.toml", "include = \"c.toml\"\n");
  d.write("presets/b.toml", "include = \"c.toml\"\n");
  d.write("presets/c.toml", kCamera);
  d.write("scene.toml", std::string("include = [\"presets/a.toml\", \"presets/b.toml\"]\n") + kSiteTime);
  CHECK(load_scene(scene).camera.lens.width == 64);
}

TEST_CASE("--set overrides any key after the includes, values parsed as TOML", "[scene][set]") {
  TempDir d;
  d.write("presets/camera.toml", kCamera);
  const std::string scene = d.write("scene.toml", std::string("include = \"presets/camera.toml\"\n") + kSiteTime);
  const auto s = load_scene(scene, {parse_override("camera.heading_deg=55.5"), parse_override("camera.model=equisolid"),
                                    parse_override("render.bands=[\"R\", \"G\", \"B\"]"),
                                    parse_override("time.instants=[2022-09-23T10:00:00+02:00]"),
                                    parse_override("output.path=out/x y.exr"), parse_override("site.height_m = 12")});
  CHECK(s.camera.heading_deg == 55.5);
  CHECK(s.camera.lens.model == "equisolid");       // a bare word is a string
  CHECK(s.render.bands == std::vector<std::string>{"R", "G", "B"});
  REQUIRE(s.times.size() == 1);
  CHECK(s.times[0].unix_seconds == 1663920000.0);  // 2022-09-23T08:00:00Z, a TOML offset date-time
  CHECK(s.output.path == "out/x y.exr");
  CHECK(s.site.height_m == 12);
  // Later overrides win over earlier ones.
  CHECK(load_scene(scene, {parse_override("camera.width=8"), parse_override("camera.width=16")}).camera.lens.width == 16);
  // The provenance text records the overrides and parses back to the same scene.
  const auto src = load_scene_source(scene, {parse_override("camera.heading_deg=55.5")});
  CHECK_THAT(src.text, Catch::Contains("camera.heading_deg=55.5   (--set)"));
  CHECK(skypol::scene::parse_scene(src.text, "again.toml").camera.heading_deg == 55.5);
}

TEST_CASE("an error from --set is reported at --set, with the column in key=value", "[scene][set][errors]") {
  TempDir d;
  const std::string scene = d.write("scene.toml", std::string(kSiteTime) + kCamera);
  CHECK_THAT(error_of(scene, {parse_override("camera.fov_deg=400")}),
             Catch::StartsWith("--set:1:16: error: key 'camera.fov_deg': value 400 out of range [1, 360]"));
  CHECK_THAT(error_of(scene, {parse_override("camera.fov_dge=100")}),
             Catch::StartsWith("--set:1:8: error: unknown key 'camera.fov_dge' (did you mean 'camera.fov_deg'?)"));
  CHECK_THAT(error_of(scene, {parse_override("camera.width=[1, 2")}), Catch::StartsWith("--set:1:"));
  CHECK_THAT(error_of(scene, {parse_override("camera.width=[1, 2")}), Catch::Contains("TOML syntax"));
  CHECK_THAT(error_of(scene, {parse_override("camera.width=wide")}),
             Catch::StartsWith("--set:1:14: error: key 'camera.width': expected an integer, found a string"));
  CHECK_THAT(error_of(scene, {parse_override("include=\"x.toml\"")}), Catch::Contains("not in an override"));
  try {
    (void)parse_override("camera.width");
    FAIL("no error");
  } catch (const SceneError& e) {
    CHECK_THAT(e.what(), Catch::StartsWith("--set: error: expected key=value"));
  }
}

TEST_CASE("to_toml writes a table that parses back equal, floats in their shortest form", "[scene][source]") {
  const toml::table t = skypol::scene::parse_toml(R"(top = 1
"key with space" = "tab\there \"quoted\" back\\slash"
floats = [0.1, 43.28699, 1e300, -0.0, 5e-324, 2.5e-8, 60.0]
when = 2022-09-23T08:00:00+02:00
day = 2022-09-23
clock = 08:30:00
flag = true
nested = [[1, 2], ["a"], [{ x = 1 }]]
inline = { a = 1, b = { c = "d" } }
[a.b]
c = 3
[[boxes]]
size = [1.5, 2.0]
[[boxes]]
size = [3.0, 1e-3]
)", "in.toml");
  const std::string text = skypol::scene::to_toml(t);
  INFO(text);
  CHECK(skypol::scene::parse_toml(text, "out.toml") == t);
  CHECK_THAT(text, Catch::Contains("floats = [0.1, 43.28699, 1e+300, -0.0, 5e-324, 2.5e-08, 60.0]"));
  CHECK_THAT(text, Catch::Contains("\n[a.b]\nc = 3\n"));
  CHECK_THAT(text, Catch::Contains("\n[[boxes]]\nsize = [1.5, 2.0]\n"));
  CHECK_THAT(text, Catch::Contains("\"key with space\" = \"tab\\there \\\"quoted\\\" back\\\\slash\""));
}

TEST_CASE("toml_quoted escapes what a TOML basic string requires, and toml++ reads the text back", "[scene]") {
  using skypol::scene::toml_quoted;
  // Each escape by itself, as TOML 1.0 writes it: \" \\ \n \t \r by name, other controls as \u00xx.
  CHECK(toml_quoted("a\"b") == R"("a\"b")");
  CHECK(toml_quoted("a\\b") == R"("a\\b")");
  CHECK(toml_quoted("\n\t\r") == R"("\n\t\r")");
  CHECK(toml_quoted(std::string("\0\x01\x08\x0c\x1f\x7f", 6)) == R"("\u0000\u0001\u0008\u000c\u001f\u007f")");
  CHECK(toml_quoted("é ∞ ok") == "\"é ∞ ok\"");  // UTF-8 kept as it is
  // Every byte that needs an escape, and some that do not, round-tripped through toml++'s parser.
  std::string text = "calib \"file\" C:\\dir\\x.yaml\nline\ttab\rcr é";
  for (int c = 0; c < 0x20; ++c) text += static_cast<char>(c);
  text += '\x7f';
  const toml::table t = toml::parse("k = " + toml_quoted(text) + "\n");
  REQUIRE(t["k"].as_string() != nullptr);
  CHECK(t["k"].as_string()->get() == text);
}
