// The [camera], [sky] and [sensor] sections: every lens model, presets, quaternions, sky options
// and the sensor arrive as written and build what they describe; their errors name the key.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "camera/orientation.h"
#include "scene/scene.h"
#include "sky/units.h"

using namespace skypol;
using scene::parse_scene;
using scene::SceneError;

namespace {

const std::string kHead = R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336

[time]
instants = ["2022-09-23T10:00:00Z"]

)";

std::string error_of(const std::string& text, const std::string& file = "bad.toml") {
  try {
    parse_scene(text, file);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("a Kannala-Brandt camera builds with its four coefficients", "[scene][camera]") {
  const auto s = parse_scene(kHead + R"([camera]
model = "kannala_brandt"
fx = 160
width = 400
height = 300
fov_deg = 185
coefficients = [0.01, -0.002, 0.0003, -0.00001]
)", "kb.toml");
  REQUIRE(s.camera.lens.coefficients.size() == 4);
  CHECK(s.camera.lens.coefficients[1] == -0.002);
  const auto cam = scene::build_camera(s.camera);
  CHECK(cam->lens().name() == "kannala_brandt");
  // θ(1 + k1θ² + …) at θ = 60°, independent of the lens code: the radius of that direction's pixel.
  const double t = kPi / 3, r = 160 * t * (1 + 0.01 * t * t - 0.002 * std::pow(t, 4) + 0.0003 * std::pow(t, 6) -
                                              0.00001 * std::pow(t, 8));
  const Eigen::Vector3d d(std::sin(t), 0, std::cos(t));
  const auto px = cam->lens().project(d);
  REQUIRE(px);
  CHECK(px->x() - 199.5 == Approx(r).epsilon(1e-12));
}

TEST_CASE("a make_lens error is reported at the key it names", "[scene][camera][errors]") {
  const std::string e = error_of(kHead + R"([camera]
model = "kannala_brandt"
fx = 160
width = 400
height = 300
fov_deg = 185
coefficients = [0.01, -0.002, 0.0003]
)");
  CHECK_THAT(e, Catch::StartsWith("bad.toml:14:"));
  CHECK_THAT(e, Catch::Contains("camera.coefficients") && Catch::Contains("needs 4"));
}

TEST_CASE("a preset lens on a preset sensor, binned", "[scene][camera]") {
  const auto s = parse_scene(kHead + R"([camera]
lens_preset = "fujinon_fe185c057ha1"
sensor_preset = "sony_imx250mzr"
binning = 4
)", "preset.toml");
  const auto cam = scene::build_camera(s.camera);
  CHECK(cam->width() == 612);
  CHECK(cam->height() == 512);
  // 1.8 mm / 3.45 µm, then 4×4 binning divides the focal length in pixels by 4.
  CHECK(cam->lens().intrinsics().fx == Approx(1.8e3 / 3.45 / 4).epsilon(1e-12));
  CHECK(cam->lens().max_field_angle() == Approx(rad_from_deg(92.5)).epsilon(1e-12));
}

TEST_CASE("a quaternion orientation is carried as heading, tilt and roll", "[scene][camera]") {
  // A camera at heading 30°, tilt 40°, roll 20°, given as the quaternion of that rotation.
  const Eigen::Quaterniond q(camera::world_from_heading_tilt_roll(30, 40, 20));
  char text[256];
  std::snprintf(text, sizeof text,
                "[camera]\nmodel = \"equidistant\"\nfx = 100\nwidth = 64\nheight = 64\nquaternion = [%.17g, %.17g, "
                "%.17g, %.17g]\n",
                q.w(), q.x(), q.y(), q.z());
  const auto s = parse_scene(kHead + text, "q.toml");
  CHECK(s.camera.heading_deg == Approx(30).margin(1e-9));
  CHECK(s.camera.tilt_deg == Approx(40).margin(1e-9));
  CHECK(s.camera.roll_deg == Approx(20).margin(1e-9));
  CHECK(error_of(kHead + text + "heading_deg = 10\n").find("not both") != std::string::npos);
}

TEST_CASE("an OCamCalib file resolves against the scene's folder and is stored absolute", "[scene][camera]") {
  const std::filesystem::path data = std::filesystem::path(SKYPOL_SOURCE_DIR) / "tests/camera/data";
  const std::string scene_file = (data / "scene.toml").string();  // never read: the text is given
  const auto s = parse_scene(kHead + "[camera]\nmodel = \"ocam\"\nocamcalib_path = \"ocam_calib_results.txt\"\n",
                             scene_file);
  CHECK(std::filesystem::path(s.camera.lens.ocamcalib_path).is_absolute());
  CHECK(std::filesystem::equivalent(s.camera.lens.ocamcalib_path, data / "ocam_calib_results.txt"));
  const auto again = scene::parse_camera(s.camera.description, "header");
  CHECK(again.lens.ocamcalib_path == s.camera.lens.ocamcalib_path);
  const std::string e =
      error_of(kHead + "[camera]\nmodel = \"ocam\"\nocamcalib_path = \"missing.txt\"\n", scene_file);
  CHECK_THAT(e, Catch::Contains("camera.ocamcalib_path") && Catch::Contains("no such file"));
}

TEST_CASE("a tabulated lens reads its (angle, height) rows", "[scene][camera]") {
  const auto s = parse_scene(kHead + R"([camera]
model = "tabulated"
pitch_um = 10
width = 200
height = 200
table = [[0, 0.0], [30, 0.3], [60, 0.6], [90, 0.9]]
)", "tab.toml");
  REQUIRE(s.camera.lens.table.size() == 4);
  const auto cam = scene::build_camera(s.camera);
  // 0.3 mm at 30° with 10 µm pixels: 30 px from the centre.
  const auto px = cam->lens().project(Eigen::Vector3d(std::sin(kPi / 6), 0, std::cos(kPi / 6)));
  REQUIRE(px);
  CHECK(px->x() - 99.5 == Approx(30).epsilon(1e-9));
  CHECK_THAT(error_of(kHead + "[camera]\nmodel = \"tabulated\"\npitch_um = 10\nwidth = 9\nheight = 9\ntable = [[0, 1, 2]]\n"),
             Catch::Contains("camera.table") && Catch::Contains("rows"));
}

TEST_CASE("sky keys: Berry's separation, Preetham's turbidity range, clouds", "[scene][sky]") {
  const std::string cam = "[camera]\nfx = 20\nwidth = 64\nheight = 64\n";
  const auto s = parse_scene(kHead + cam + R"([sky]
model = "berry"
separation_deg = 12
max_dolp = 0.7
intensity = "preetham"
turbidity = 3
[sky.clouds]
coverage = 0.4
seed = 7
)", "sky.toml");
  CHECK(s.sky.model == "berry");
  CHECK(s.sky.separation_deg == 12);
  CHECK(s.sky.clouds.coverage == 0.4);
  CHECK(s.sky.clouds.seed == 7);
  CHECK(scene::build_sky(s.sky)->name() == "berry");
  CHECK_THAT(error_of(kHead + cam + "[sky]\nseparation_deg = 12\n"), Catch::Contains("only by model \"berry\""));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nintensity = \"preetham\"\nturbidity = 1.5\n"),
             Catch::Contains("sky.turbidity") && Catch::Contains("[2, 10]"));
  CHECK_THAT(error_of(kHead + cam + "[sky.clouds]\ncovrage = 0.4\n"),
             Catch::Contains("unknown key 'sky.clouds.covrage'") && Catch::Contains("did you mean 'sky.clouds.coverage'"));
}

TEST_CASE("sensor keys: a preset, overrides, and the errors of a sensor that cannot work", "[scene][sensor]") {
  const std::string cam = "[camera]\nfx = 20\nwidth = 64\nheight = 48\n";
  const auto s = parse_scene(kHead + cam + "[sensor]\npreset = \"sony_imx250mzr\"\nread_noise_e = 5\n", "s.toml");
  REQUIRE(s.sensor);
  CHECK(s.sensor->dofp.width == 64);  // the camera's size, not the preset's
  CHECK(s.sensor->dofp.height == 48);
  CHECK(s.sensor->dofp.read_noise_e == 5);
  CHECK(s.sensor->dofp.full_well_e == 11000);  // from the preset
  CHECK_FALSE(parse_scene(kHead + cam, "none.toml").sensor);  // no section, no sensor
  CHECK_THAT(error_of(kHead + cam + "[sensor]\ncolor_filter = \"rggb_blocks\"\n"),
             Catch::Contains("sensor.color_filter") && Catch::Contains("bands R, G, B"));
  CHECK_THAT(error_of(kHead + cam + "[sensor]\nmosaic_deg = [0, 45, 90]\n"),
             Catch::Contains("sensor.mosaic_deg") && Catch::Contains("4 numbers"));
  CHECK_THAT(error_of(kHead + cam + "[sensor]\npreset = \"nikon\"\n"),
             Catch::Contains("sensor.preset") && Catch::Contains("sony_imx250mzr"));
}

TEST_CASE("exposure: fixed by default, \"auto\" with the meter's keys; errors at file:line and key", "[scene][sensor][errors]") {
  const std::string cam = "[camera]\nfx = 20\nwidth = 64\nheight = 48\n";
  // kHead and cam take lines 1-11; [sensor] is line 12, its first key line 13.
  const auto fixed = parse_scene(kHead + cam + "[sensor]\nexposure_us = 250\n", "fixed.toml");
  REQUIRE(fixed.sensor);
  CHECK_FALSE(fixed.sensor->auto_exposure);
  CHECK(fixed.sensor->dofp.exposure_us == 250);
  const auto def = parse_scene(kHead + cam + "[sensor]\nexposure = \"auto\"\n", "auto.toml");
  REQUIRE(def.sensor->auto_exposure);
  CHECK(def.sensor->auto_exposure->percentile == 99.5);  // the reproduction protocol's meter
  CHECK(def.sensor->auto_exposure->target == 0.8);
  CHECK(def.sensor->auto_exposure->step_us == 0);
  const auto set = parse_scene(kHead + cam +
                                   "[sensor]\nexposure = \"auto\"\nauto_exposure_percentile = 99\nauto_exposure_target = 0.5\n"
                                   "auto_exposure_min_us = 20\nauto_exposure_max_us = 5e5\nauto_exposure_step_us = 10\n",
                               "set.toml");
  const camera::AutoExposure& m = *set.sensor->auto_exposure;
  CHECK((m.percentile == 99 && m.target == 0.5 && m.min_us == 20 && m.max_us == 5e5 && m.step_us == 10));

  const std::string head = kHead + cam + "[sensor]\n";
  CHECK_THAT(error_of(head + "exposure = \"automatic\"\n"),
             Catch::StartsWith("bad.toml:13:") && Catch::Contains("sensor.exposure") && Catch::Contains("auto"));
  CHECK_THAT(error_of(head + "exposure = \"auto\"\nauto_exposure_target = 1.5\n"),
             Catch::StartsWith("bad.toml:14:") && Catch::Contains("sensor.auto_exposure_target") && Catch::Contains("[0, 1]"));
  CHECK_THAT(error_of(head + "exposure = \"auto\"\nauto_exposure_target = 0\n"),
             Catch::StartsWith("bad.toml:14:") && Catch::Contains("sensor.auto_exposure_target") && Catch::Contains("(0, 1]"));
  CHECK_THAT(error_of(head + "exposure = \"auto\"\nauto_exposure_percentile = 0\n"),
             Catch::StartsWith("bad.toml:14:") && Catch::Contains("sensor.auto_exposure_percentile"));
  // A meter key without the meter, and a fixed exposure beside it, would be silently ignored.
  CHECK_THAT(error_of(head + "auto_exposure_target = 0.5\n"),
             Catch::StartsWith("bad.toml:13:") && Catch::Contains("sensor.auto_exposure_target") &&
                 Catch::Contains("exposure = \"auto\""));
  CHECK_THAT(error_of(head + "exposure = \"auto\"\nexposure_us = 500\n"),
             Catch::StartsWith("bad.toml:14:") && Catch::Contains("sensor.exposure_us"));
  CHECK_THAT(error_of(head + "exposure = \"auto\"\nauto_exposure_min_us = 2e7\n"),
             Catch::StartsWith("bad.toml:14:") && Catch::Contains("sensor.auto_exposure_min_us") &&
                 Catch::Contains("range is empty"));
}

TEST_CASE("a scene of night frames only is refused, naming its time key", "[scene][errors]") {
  // Marseille at 22:00–23:00 UTC in September: the sun is far below the horizon.
  const std::string e = error_of(R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336
[time]
start = "2022-09-23T22:00:00Z"
end = "2022-09-23T23:00:00Z"
step_min = 30
[camera]
fx = 20
width = 64
height = 64
)");
  CHECK_THAT(e, Catch::StartsWith("bad.toml:5:") && Catch::Contains("time.start") && Catch::Contains("below the horizon"));
}

TEST_CASE("the raw mosaic is a channel only with a sensor", "[scene][sensor][errors]") {
  const std::string cam = "[camera]\nfx = 20\nwidth = 64\nheight = 48\n";
  const auto s = parse_scene(kHead + cam + "[sensor]\n[output]\nchannels = [\"DoLP\", \"raw\"]\n", "raw.toml");
  CHECK(s.output.channels.back() == "raw");
  CHECK_THAT(error_of(kHead + cam + "[output]\nchannels = [\"DoLP\", \"raw\"]\n"),
             Catch::Contains("output.channels") && Catch::Contains("needs a [sensor]"));
}

TEST_CASE("vrte sky keys: aerosol, albedo, accuracy, wavelengths; errors at the key", "[scene][sky][vrte]") {
  const std::string cam = "[camera]\nfx = 20\nwidth = 64\nheight = 64\n";
  const auto s = parse_scene(kHead + cam + R"([sky]
model = "vrte"
ground_albedo = 0.2
streams = 8
grid = 17
[sky.aerosol]
type = "maritime_clean"
tau_550 = 0.05
angstrom = 0.4
ssa = 0.98
[render]
bands = ["R", "G", "B"]
)", "vrte.toml");
  CHECK(s.sky.model == "vrte");
  CHECK(s.sky.ground_albedo == 0.2);
  CHECK(s.sky.streams == 8);
  CHECK(s.sky.grid == 17);
  CHECK(s.sky.aerosol.type == "maritime_clean");
  CHECK(s.sky.aerosol.tau_550 == 0.05);
  CHECK(s.sky.aerosol.angstrom == 0.4);
  CHECK(s.sky.aerosol.ssa == 0.98);
  // No pressure in the scene: the Rayleigh depth uses 1013.25 hPa; the site's height and latitude.
  CHECK(scene::site_atmosphere(s).pressure_hpa == 1013.25);
  CHECK(scene::site_atmosphere(s).latitude_deg == 43.28699);

  const auto custom = parse_scene(kHead + cam + "[sky]\nmodel = \"vrte\"\nwavelengths_nm = [440]\n"
                                  "[sky.aerosol]\ntype = \"custom\"\nmedian_radius_um = 0.2\ngeometric_std = 1.8\n"
                                  "refractive_real = 1.45\nrefractive_imag = 0.01\n", "c.toml");
  CHECK(custom.sky.wavelengths_nm == std::vector<double>{440});
  CHECK(custom.sky.aerosol.median_radius_um == 0.2);
  CHECK(custom.sky.aerosol.refractive_imag == 0.01);

  // Each error names the file, the line and column of the key, and the key.
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"rayleigh\"\nground_albedo = 0.2\n"),
             Catch::StartsWith("bad.toml:14:17") && Catch::Contains("'sky.ground_albedo'") &&
                 Catch::Contains("only by model \"vrte\""));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"vrte\"\nmax_dolp = 0.8\n"),
             Catch::StartsWith("bad.toml:14:12") && Catch::Contains("'sky.max_dolp'") &&
                 Catch::Contains("not used by model \"vrte\""));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"vrte\"\n[sky.aerosol]\ntau_550 = 20\n"),
             Catch::StartsWith("bad.toml:15:11") && Catch::Contains("'sky.aerosol.tau_550'") &&
                 Catch::Contains("[0, 10]"));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"vrte\"\n[sky.aerosol]\ntype = \"volcanic\"\n"),
             Catch::StartsWith("bad.toml:15:8") && Catch::Contains("'sky.aerosol.type'") &&
                 Catch::Contains("continental_clean"));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"vrte\"\n[sky.aerosol]\nmedian_radius_um = 0.3\n"),
             Catch::StartsWith("bad.toml:15:20") && Catch::Contains("only by type \"custom\""));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"vrte\"\nstreams = 2\n"),
             Catch::StartsWith("bad.toml:14:11") && Catch::Contains("'sky.streams'"));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"vrte\"\nwavelengths_nm = [450, 550]\n"),
             Catch::StartsWith("bad.toml:14:18") && Catch::Contains("'sky.wavelengths_nm'") &&
                 Catch::Contains("2 wavelength(s) for 1 band(s)"));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"vrte\"\n[render]\nbands = [\"NIR\"]\n"),
             Catch::Contains("'sky.wavelengths_nm'") && Catch::Contains("band \"NIR\""));
  CHECK_THAT(error_of(kHead + cam + "[sky]\nmodel = \"vrte\"\n[sky.aerosol]\ntpye = \"urban\"\n"),
             Catch::Contains("unknown key 'sky.aerosol.tpye'") && Catch::Contains("did you mean 'sky.aerosol.type'"));
}
