// The sky models' and the lenses' registries (sky/sky_model_registry.h, camera/lens_registry.h): a
// model registered at run time is seen by the scene language and the factories with no other
// edit; switching a scene's sky model with an override drops the old model's keys; `--set KEY=`
// unsets a key.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "camera/lens_registry.h"
#include "camera/radial_lens.h"
#include "scene/scene.h"
#include "sky/sky_model_registry.h"
#include "sky/units.h"

using namespace skypol;

namespace {

// A sky of radiance 1 everywhere, polarized along e0 with a degree from its own key.
class FlatSky final : public sky::SkyModel {
 public:
  explicit FlatSky(double degree) : degree_(degree) {}
  using sky::SkyModel::stokes;
  std::string name() const override { return "flat"; }
  sky::Stokes stokes(const Eigen::Vector3d&, const Eigen::Vector3d&, const sky::Sun&) const override {
    return sky::Stokes{1.0, degree_, 0.0, 0.0};
  }

 private:
  double degree_;
};

const bool kFlatRegistered = [] {
  sky::SkyModelEntry e;
  e.name = "flat";
  e.description = "test: uniform radiance, degree `degree` along e0";
  e.keys = {sky::param_number_key("degree", 0.25, 0, 1)};
  e.make = [](const sky::SkySpec& s) -> std::unique_ptr<sky::SkyModel> {
    return std::make_unique<FlatSky>(sky::param_number(s, "degree"));
  };
  sky::register_sky_model(e);
  camera::LensModel l;
  l.name = "test_linear";
  l.description = "test: r = f θ under another name";
  l.hemisphere_default = true;
  l.make = [](const camera::LensSpec& s) -> std::shared_ptr<const camera::Lens> {
    camera::Intrinsics k;
    k.width = s.width;
    k.height = s.height;
    k.fx = k.fy = *s.fx;
    k.cx = 0.5 * (s.width - 1);
    k.cy = 0.5 * (s.height - 1);
    return std::make_shared<camera::RadialLens>(camera::Mapping::equidistant, k, rad_from_deg(0.5 * *s.fov_deg));
  };
  camera::register_lens_model(l);
  return true;
}();

const std::string kHead = R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336

[time]
instants = ["2022-09-23T10:00:00Z"]

[camera]
model = "equidistant"
width = 64
height = 64
fx = 20

)";

std::string error_of(const std::string& text, const std::vector<scene::Override>& overrides = {}) {
  try {
    (void)scene::scene_from_source(scene::parse_scene_source(text, "bad.toml", overrides));
  } catch (const scene::SceneError& e) {
    return e.what();
  }
  return "no error";
}

scene::Scene with(const std::string& text, const std::vector<std::string>& sets) {
  std::vector<scene::Override> o;
  for (const std::string& s : sets) o.push_back(scene::parse_override(s));
  return scene::scene_from_source(scene::parse_scene_source(text, "scene.toml", o));
}

}  // namespace

TEST_CASE("a sky model registered at run time is a [sky] model with its own keys", "[scene][registry]") {
  REQUIRE(kFlatRegistered);
  const std::vector<std::string> names = sky::sky_model_names();
  CHECK(std::find(names.begin(), names.end(), "flat") != names.end());
  const sky::Sun sun = sky::sun_from_horizontal(0.0, 0.5, 43.0);
  const Eigen::Vector3d up(0, 0, 1), east(1, 0, 0);

  const scene::Scene s = scene::parse_scene(kHead + "[sky]\nmodel = \"flat\"\ndegree = 0.6\n", "flat.toml");
  CHECK(s.sky.model == "flat");
  const sky::Stokes st = scene::build_sky(s.sky)->stokes(up, east, sun);
  CHECK(st.s0 == 1.0);
  CHECK(st.s1 == Approx(0.6));
  // Its default is its own, and the wrappers every model takes wrap it: under full cover the
  // zenith is cloud, not the flat sky.
  const scene::Scene d = scene::parse_scene(kHead + "[sky]\nmodel = \"flat\"\n", "flat.toml");
  CHECK(scene::build_sky(d.sky)->stokes(up, east, sun).s1 == Approx(0.25));
  const scene::Scene cloudy = scene::parse_scene(kHead + "[sky]\nmodel = \"flat\"\n[sky.clouds]\ncoverage = 1\n", "flat.toml");
  CHECK(cloudy.sky.clouds.coverage == 1);
  const sky::Stokes under = scene::build_sky(cloudy.sky)->stokes(up, east, sun);
  CHECK((under.s0 != 1.0 || under.s1 != Approx(0.25)));

  // Its key with another model, another model's key with it, a value out of its range.
  CHECK_THAT(error_of(kHead + "[sky]\ndegree = 0.6\n"),
             Catch::StartsWith("bad.toml:15:10") && Catch::Contains("'sky.degree'") &&
                 Catch::Contains("used only by model \"flat\""));
  CHECK_THAT(error_of(kHead + "[sky]\nmodel = \"flat\"\nmax_dolp = 0.6\n"),
             Catch::StartsWith("bad.toml:16:12") &&
                 Catch::Contains("not used by model \"flat\""));
  CHECK_THAT(error_of(kHead + "[sky]\nmodel = \"flat\"\ndegree = 2\n"),
             Catch::StartsWith("bad.toml:16:10") && Catch::Contains("[0, 1]"));
  // A spec built in code is checked with the same range.
  sky::SkySpec spec;
  spec.model = "flat";
  spec.params["degree"] = 1.5;
  CHECK_THROWS_WITH(sky::make_sky(spec), Catch::StartsWith("sky.degree: 1.5 is outside [0, 1]"));
}

TEST_CASE("--set sky.model switches the scene's sky: the files' keys of the old model are dropped",
          "[scene][registry][override]") {
  const std::string grey = kHead + "[sky]\nmodel = \"rayleigh\"\nmax_dolp = 0.7\nturbidity = 4\nsun_disc = true\n";
  // Today's scene, then the same scene under the VRTE sky and under the registered one.
  CHECK(with(grey, {}).sky.max_dolp == 0.7);
  const scene::Scene v = with(grey, {"sky.model=vrte"});
  CHECK(v.sky.model == "vrte");
  CHECK(v.sky.sun_disc);  // every model takes it: kept
  REQUIRE(v.notes.size() == 2);
  CHECK_THAT(v.notes[0], Catch::StartsWith("sky.max_dolp (scene.toml:16) dropped: model \"vrte\""));
  CHECK_THAT(v.notes[1], Catch::StartsWith("sky.turbidity (scene.toml:17) dropped"));
  // The provenance text is the scene as rendered: it reads back to the same sky, with no note.
  const scene::Scene again = scene::parse_scene(v.text, "header");
  CHECK(again.sky.model == "vrte");
  CHECK(again.notes.empty());
  const scene::Scene f = with(grey, {"sky.model=flat", "sky.degree=0.1"});
  CHECK(scene::build_sky(f.sky)->stokes(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0),
                                        sky::sun_from_horizontal(0, 0.5, 43)).s1 == Approx(0.1));
  // Back the other way: vrte's keys and its [sky.aerosol] go when a grey model is asked for.
  const std::string vrte = kHead + "[sky]\nmodel = \"vrte\"\nstreams = 8\n[sky.aerosol]\ntau_550 = 0.2\n";
  const scene::Scene b = with(vrte, {"sky.model=berry", "sky.separation_deg=10"});
  CHECK(b.sky.model == "berry");
  CHECK(b.sky.separation_deg == 10);
  CHECK(b.sky.streams == sky::SkySpec{}.streams);
  CHECK(b.sky.aerosol.tau_550 == sky::SkySpec{}.aerosol.tau_550);
  CHECK(b.notes.size() == 2);

  // A key given on the command line for the wrong model stays an error, at the override.
  CHECK_THAT(error_of(grey, {scene::parse_override("sky.model=vrte"), scene::parse_override("sky.max_dolp=0.5")}),
             Catch::StartsWith("--set:1:14") &&
                 Catch::Contains("not used by model \"vrte\""));
  // A key no model takes is not dropped: it is an unknown key, at its line.
  CHECK_THAT(error_of(grey + "max_dolpp = 1\n", {scene::parse_override("sky.model=vrte")}),
             Catch::StartsWith("bad.toml:19") && Catch::Contains("unknown key 'sky.max_dolpp'"));
  // Without a model switch nothing is dropped: the scene's own mistake is still reported.
  CHECK_THAT(error_of(kHead + "[sky]\nmodel = \"vrte\"\nmax_dolp = 0.7\n", {scene::parse_override("camera.fx=21")}),
             Catch::StartsWith("bad.toml:16:12"));
}

TEST_CASE("--set KEY= unsets a key whichever file wrote it", "[scene][override]") {
  const std::string grey = kHead + "[sky]\nmodel = \"rayleigh\"\nmax_dolp = 0.7\n";
  CHECK(with(grey, {"sky.max_dolp="}).sky.max_dolp == 1.0);
  CHECK(with(grey, {"sky="}).sky.model == "rayleigh");
  CHECK_THAT(error_of(grey, {scene::parse_override("sky.max_dolpp=")}),
             Catch::StartsWith("--set:1:1") && Catch::Contains("nothing to unset"));
}

TEST_CASE("a lens registered at run time is a [camera] model", "[scene][registry][camera]") {
  REQUIRE(kFlatRegistered);
  const auto& names = camera::lens_model_names();
  CHECK(std::find(names.begin(), names.end(), "test_linear") != names.end());
  const std::string site = "[site]\nlatitude_deg = 43\nlongitude_deg = 5\n[time]\ninstants = [\"2022-09-23T10:00:00Z\"]\n";
  const scene::Scene s =
      scene::parse_scene(site + "[camera]\nmodel = \"test_linear\"\nwidth = 201\nheight = 201\nfx = 100\n", "lens.toml");
  // Its trait: a hemisphere unless told; r = f θ about the centre (100, 100).
  REQUIRE(s.camera.lens.fov_deg);
  CHECK(*s.camera.lens.fov_deg == 180);
  const auto cam = scene::build_camera(s.camera);
  const double th = std::numbers::pi / 4;
  const auto p = cam->lens().project(Eigen::Vector3d(std::sin(th), 0, std::cos(th)));
  REQUIRE(p);
  CHECK((*p)(0) == Approx(100 + 100 * th));
  CHECK((*p)(1) == Approx(100));
  // The optional fields it does not take are refused by make_lens, at the key.
  CHECK_THAT(error_of(site + "[camera]\nmodel = \"test_linear\"\nwidth = 201\nheight = 201\nfx = 100\ncoefficients = [1, 2]\n"),
             Catch::Contains("'camera.coefficients'") &&
                 Catch::Contains("coefficients: not used by model test_linear"));
}
