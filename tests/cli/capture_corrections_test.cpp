// `skypol import` keeps a capture's dark and flat corrections in floating point: a tenth of a DN of
// dark, or a flat of 1.01 on 10 DN, moves the Stokes values by what it should, where rounding the
// corrected mosaic back to whole DN would leave such changes at zero. The stack holds half floats
// (the renders' default), which resolve 0.005 DN at this level.
#include <catch2/catch.hpp>

#include <cmath>

#include "cli/cli_harness.h"
#include "stack/npy.h"
#include "stack/stack_io.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

constexpr std::size_t kRows = 128, kCols = 153;  // the preset sensor at binning 16

const char* kCapture = R"([capture]
frames = ["raw.npy"]
times = "csv"
times_csv = "times.csv"
dark = "dark.npy"
flat = "flat.npy"

[camera]
lens_preset = "fujinon_fe185c057ha1"
sensor_preset = "sony_imx250mzr"
binning = 16

[sensor]
preset = "sony_imx250mzr"
exposure_us = 4000
)";

// S0 at the image centre of a capture of a uniform 20 DN mosaic with a uniform dark and flat.
double centre_s0(const TempDir& dir, float dark, float flat) {
  const std::vector<std::size_t> shape{kRows, kCols};
  std::vector<unsigned short> raw(kRows * kCols, 20);
  std::vector<float> d(raw.size(), dark), f(raw.size(), flat);
  REQUIRE(skypol::stack::write_npy((dir.path / "raw.npy").string(), shape, raw.data()));
  REQUIRE(skypol::stack::write_npy((dir.path / "dark.npy").string(), shape, d.data()));
  REQUIRE(skypol::stack::write_npy((dir.path / "flat.npy").string(), shape, f.data()));
  dir.write("times.csv", "file,time\nraw.npy,2022-06-21T07:00:00Z\n");
  const std::string capture = dir.write("capture.toml", kCapture);
  const std::string out = (dir.path / "c.exr").string();
  const Result r = run("import -q " + capture + " -o " + out);
  INFO(r.out);
  REQUIRE(r.code == 0);
  const skypol::stack::Stack st = skypol::stack::read_stack(out, {"S0.Y"});
  return static_cast<double>(st.frames.at(0).channel("S0.Y").at((kRows / 2) * kCols + kCols / 2));
}

}  // namespace

TEST_CASE("dark and flat corrections are kept in floating point", "[cli][capture]") {
  TempDir dir;
  // S0 is linear in the corrected DN (S0 ∝ raw − dark: the import puts the sensor's mean dark signal
  // back, the demosaic takes it off): equal steps of dark give equal, non-zero steps of S0.
  const double a = centre_s0(dir, 10.0f, 1.0f), b = centre_s0(dir, 10.1f, 1.0f), c = centre_s0(dir, 10.2f, 1.0f);
  INFO("S0 " << a << " " << b << " " << c);
  REQUIRE(a > b);
  REQUIRE(b > c);
  CHECK(std::abs((a - b) - (b - c)) < 0.1 * (a - b));
  // 0.1 DN is 1 % of the 10 DN above the dark (to within the half floats' rounding).
  CHECK(std::abs((a - b) / a - 0.01) < 0.001);
  // A flat of 1.01 divides the dark-subtracted signal by it: 0.1 DN here.
  const double e = centre_s0(dir, 10.0f, 1.01f);
  CHECK(std::abs(a / e - 1.01) < 0.001);
}
