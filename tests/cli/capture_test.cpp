// Real captures in (`skypol import`) and frames out (`skypol export`): a rendered stack's raw
// mosaics, written as a camera SDK writes them (16-bit PNG, TIFF, NumPy .npy), come back through
// `skypol import` to the very Stokes values the renderer's sensor stage produced (the same
// integers through the same demosaic, so equality is exact, not within quantization) and to the
// same estimate, printed without scores; and every error class of a capture exits 2 naming the
// file, with nothing written.
#include <catch2/catch.hpp>

#include <cmath>
#include <regex>

#include "cli/cli_harness.h"
#include "stack/npy.h"
#include "stack/stack_io.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

// The camera and sensor sections, shared by the scene and the capture files (as a user copies
// their calibration into both).
const char* kCamera = R"([camera]
lens_preset = "fujinon_fe185c057ha1"
sensor_preset = "sony_imx250mzr"
binning = 8
tilt_deg = 3
roll_deg = -2

[sensor]
preset = "sony_imx250mzr"
exposure_us = 4000
seed = 7
)";

std::string scene_text() {
  return std::string(R"([site]
latitude_deg = 43.3
longitude_deg = 5.4

[time]
start = "2022-06-21T05:00:00Z"
end = "2022-06-21T13:00:00Z"
step_min = 60

[output]
channels = ["S0", "S1", "S2", "DoLP", "AoLP", "mask", "raw"]

)") + kCamera;
}

// kCamera ends in [sensor]: `sensor_extra` adds keys to it.
std::string capture_text(const std::string& frames, const std::string& times, const std::string& sensor_extra = "") {
  return "[capture]\nframes = [\"" + frames + "\"]\n" + times + "\n" +
         "[site]\nlatitude_deg = 43.3\nlongitude_deg = 5.4\n\n" + kCamera + sensor_extra;
}

// The "heading_deg": value of the first estimate in `estimate --json` output.
std::string json_number(const std::string& out, const std::string& key) {
  std::smatch m;
  REQUIRE(std::regex_search(out, m, std::regex("\"" + key + "\": ([^,]+),")));
  return m[1].str();
}

void require_same_stokes(const std::string& rendered, const std::string& imported) {
  const skypol::stack::Stack a = skypol::stack::read_stack(rendered);
  const skypol::stack::Stack b = skypol::stack::read_stack(imported);
  REQUIRE(b.frames.size() == a.frames.size());
  CHECK(a.truth_known);
  CHECK_FALSE(b.truth_known);
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    CHECK(b.frames[i].truth.time.unix_seconds == a.frames[i].truth.time.unix_seconds);
    // The capture's sun comes from its site and time, as the renderer's does.
    CHECK(b.frames[i].truth.sun.azimuth == Approx(a.frames[i].truth.sun.azimuth).margin(1e-12));
    for (const char* c : {"mask", "clipped", "S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y"}) {
      INFO("frame " << i << " channel " << c);
      const std::vector<float>& x = a.frames[i].channel(c);
      const std::vector<float>& y = b.frames[i].channel(c);
      REQUIRE(x.size() == y.size());
      std::size_t differ = 0;
      for (std::size_t k = 0; k < x.size(); ++k) differ += x[k] != y[k] ? 1 : 0;
      CHECK(differ == 0);
    }
  }
}

}  // namespace

TEST_CASE("raw frames as PNG, TIFF and NPY come back to the same Stokes values and the same estimate", "[cli][capture]") {
  TempDir dir;
  const std::string scene = dir.write("marseille.toml", scene_text());
  const std::string stack = (dir.path / "rendered.exr").string();
  Result r = run("render -q " + scene + " --set camera.heading_deg=37 -o " + stack);
  INFO(r.out);
  REQUIRE(r.code == 0);
  const Result truth = run("estimate -q " + stack + " -m classic --json");
  INFO(truth.out);
  REQUIRE(truth.code == 0);
  const std::string heading = json_number(truth.out, "heading_deg");

  // Times from the file names (PNG), from the TIFF's DateTime tags, and from export's times.csv (NPY).
  const std::vector<std::pair<std::string, std::string>> routes{
      {"png", "times = \"name\""}, {"tiff", "times = \"exif\""}, {"npy", "times = \"csv\"\ntimes_csv = \"npy/times.csv\""}};
  for (const auto& [format, times] : routes) {
    SECTION(format) {
      r = run("export -q " + stack + " -f " + format + " -c raw -o " + (dir.path / format).string());
      INFO(r.out);
      REQUIRE(r.code == 0);
      const std::string capture = dir.write("capture.toml", capture_text(format + "/rendered_*." + format, times));
      const std::string imported = (dir.path / ("imported-" + format + ".exr")).string();
      r = run("import -q " + capture + " -o " + imported);
      INFO(r.out);
      REQUIRE(r.code == 0);
      require_same_stokes(stack, imported);

      const Result e = run("estimate -q " + imported + " -m classic --json");
      INFO(e.out);
      REQUIRE(e.code == 0);
      CHECK(json_number(e.out, "heading_deg") == heading);
      CHECK(json_number(e.out, "truth_known") == "false");
      CHECK(json_number(e.out, "true_heading_deg") == "null");
      CHECK(json_number(e.out, "bearing_error_deg") == "null");
      const Result text = run("estimate -q " + imported + " -m classic");
      CHECK_THAT(text.out, Catch::Contains("truth unknown, nothing to score"));
      CHECK_THAT(text.out, !Catch::Contains("error"));
    }
  }
}

TEST_CASE("a colour capture (RGGB over the polarizers) comes back to the rendered R, G, B Stokes values", "[cli][capture]") {
  TempDir dir;
  const std::string colour = R"([site]
latitude_deg = 43.3
longitude_deg = 5.4

[time]
instants = ["2022-06-21T07:00:00Z", "2022-06-21T09:00:00Z"]

[render]
bands = ["R", "G", "B"]

[output]
channels = ["S0", "S1", "S2", "DoLP", "AoLP", "mask", "raw"]

[camera]
lens_preset = "fujinon_fe185c057ha1"
sensor_preset = "sony_imx250mzr"
binning = 8

[sensor]
preset = "lucid_phx050s_qc"
)";
  const std::string scene = dir.write("colour.toml", colour);
  const std::string stack = (dir.path / "colour.exr").string();
  Result r = run("render -q " + scene + " --set camera.heading_deg=37 -o " + stack);
  INFO(r.out);
  REQUIRE(r.code == 0);
  r = run("export -q " + stack + " -f png -c raw -o " + (dir.path / "raw").string());
  REQUIRE(r.code == 0);
  const std::string capture = dir.write("capture.toml", R"([capture]
frames = ["raw/*.png"]

[camera]
lens_preset = "fujinon_fe185c057ha1"
sensor_preset = "sony_imx250mzr"
binning = 8

[sensor]
preset = "lucid_phx050s_qc"
)");
  const std::string imported = (dir.path / "imported.exr").string();
  r = run("import -q " + capture + " -o " + imported);
  INFO(r.out);
  REQUIRE(r.code == 0);
  const skypol::stack::Stack a = skypol::stack::read_stack(stack);
  const skypol::stack::Stack b = skypol::stack::read_stack(imported);
  REQUIRE(b.bands == std::vector<std::string>{"R", "G", "B"});
  CHECK_FALSE(b.site_known);
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    for (const char* c : {"S0.R", "S1.G", "S2.B", "DoLP.G", "AoLP.R", "R", "mask", "clipped"}) {
      INFO(c);
      CHECK(a.frames[i].channel(c) == b.frames[i].channel(c));
    }
  }
  // Without the site the ephemeris method has nothing to work with, and says so.
  const Result e = run("estimate -q " + imported + " -m sun_vector_ephemeris");
  CHECK(e.code == 2);
  CHECK_THAT(e.out, Catch::Contains("site") && Catch::Contains("unknown"));
  const Result info = run("info " + imported);
  CHECK_THAT(info.out, Catch::Contains("truth: unknown") && Catch::Contains("site unknown"));
}

TEST_CASE("a dark frame is subtracted and a flat field divided before the demosaic", "[cli][capture]") {
  TempDir dir;
  const std::string scene = dir.write("marseille.toml", scene_text());
  const std::string stack = (dir.path / "rendered.exr").string();
  // Without dark current (and the preset's black level of 0) the sensor adds no offset to the raw
  // values, so that the dark frame below is the camera's whole dark signal and the corrected
  // mosaic is exactly the rendered one (the import keeps corrections in floating point).
  Result r = run("render -q " + scene + " --set camera.heading_deg=37 --set 'time.end=\"2022-06-21T06:00:00Z\"' "
                 "--set sensor.dark_current_e_s=0 -o " + stack);
  INFO(r.out);
  REQUIRE(r.code == 0);
  r = run("export -q " + stack + " -f npy -c raw -o " + (dir.path / "raw").string());
  REQUIRE(r.code == 0);
  // Each frame as a camera with a 100 DN dark offset and a response of 2 (even columns) or 1 (odd
  // columns) records it: raw · flat + dark (16-bit, as the values may now pass 4095).
  std::vector<std::size_t> shape;
  for (const auto& e : fs::directory_iterator(dir.path / "raw")) {
    if (e.path().extension() != ".npy") continue;
    const skypol::stack::NpyArray a = skypol::stack::read_npy(e.path().string());
    shape = a.shape;
    std::vector<unsigned short> recorded(a.values.size());
    for (std::size_t k = 0; k < a.values.size(); ++k) {
      recorded[k] = static_cast<unsigned short>(a.values[k] * ((k % a.shape[1]) % 2 == 0 ? 2 : 1) + 100);
    }
    fs::create_directories(dir.path / "recorded");
    REQUIRE(skypol::stack::write_npy((dir.path / "recorded" / e.path().filename()).string(), a.shape, recorded.data()));
  }
  REQUIRE(shape.size() == 2);
  std::vector<float> dark(shape[0] * shape[1], 100.0f), flat(dark.size());
  for (std::size_t k = 0; k < flat.size(); ++k) flat[k] = (k % shape[1]) % 2 == 0 ? 2.0f : 1.0f;
  REQUIRE(skypol::stack::write_npy((dir.path / "dark.npy").string(), shape, dark.data()));
  REQUIRE(skypol::stack::write_npy((dir.path / "flat.npy").string(), shape, flat.data()));
  fs::copy(dir.path / "raw" / "times.csv", dir.path / "recorded" / "times.csv");
  // The preset's black level and mean dark signal are in what the dark frame measures: the import
  // puts them back after the subtraction, and the demosaic takes them off again.
  const std::string capture = dir.write(
      "capture.toml", capture_text("recorded/*.npy", "times = \"csv\"\ntimes_csv = \"recorded/times.csv\"\n"
                                   "dark = \"dark.npy\"\nflat = \"flat.npy\"", "adc_bits = 16\ndark_current_e_s = 0\n"));
  const std::string imported = (dir.path / "imported.exr").string();
  r = run("import -q " + capture + " -o " + imported);
  INFO(r.out);
  REQUIRE(r.code == 0);
  require_same_stokes(stack, imported);
}
