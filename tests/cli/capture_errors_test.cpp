// Every error class of `skypol import` (the capture file, a frame, the times) and of `skypol
// export`: exit 2, a message naming the file (and the key or line), and no output left behind.
#include <catch2/catch.hpp>

#include <fstream>

#include "cli/cli_harness.h"
#include "stack/npy.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

// A 16x12 camera: small enough to write its frames by hand.
const char* kCamera = R"([camera]
model = "equidistant"
width = 16
height = 12
fx = 4
fov_deg = 180

[sensor]
preset = "sony_imx250mzr"
)";

void write_frame(const fs::path& path, unsigned short value, std::size_t rows = 12, std::size_t cols = 16) {
  std::vector<unsigned short> v(rows * cols, value);
  REQUIRE(skypol::stack::write_npy(path.string(), {rows, cols}, v.data()));
}

// Writes raw npy frames f_20220621T0{6,7}0000.npy and returns the capture file's path.
std::string setup(const TempDir& dir, const std::string& capture_section, const std::string& after = "") {
  write_frame(dir.path / "f_20220621T060000.npy", 500);
  write_frame(dir.path / "f_20220621T070000.npy", 600);
  return dir.write("capture.toml", capture_section + "\n" + kCamera + after);
}

void expect_error(const std::string& capture, const TempDir& dir, const std::string& what1, const std::string& what2) {
  const std::string out = (dir.path / "out.exr").string();
  const Result r = run("import -q " + capture + " -o " + out);
  INFO(r.out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains(what1));
  CHECK_THAT(r.out, Catch::Contains(what2));
  CHECK_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(dir.path)) CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
}

}  // namespace

TEST_CASE("a good hand-made capture imports, with its times from the names", "[cli][capture]") {
  TempDir dir;
  const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
  const std::string out = (dir.path / "out.exr").string();
  const Result r = run("import -q " + capture + " -o " + out);
  INFO(r.out);
  REQUIRE(r.code == 0);
  const Result info = run("info " + out);
  CHECK_THAT(info.out, Catch::Contains("2022-06-21T06:00:00Z") && Catch::Contains("2022-06-21T07:00:00Z"));
  CHECK_THAT(info.out, Catch::Contains("truth: unknown"));
  // evaluate has nothing to score: refused when named, skipped in a folder.
  const Result ev = run("evaluate " + out);
  CHECK(ev.code == 2);
  CHECK_THAT(ev.out, Catch::Contains("imported capture") && Catch::Contains("nothing to score"));
  const Result folder = run("evaluate " + dir.path.string());
  CHECK(folder.code == 2);
  CHECK_THAT(folder.out, Catch::Contains("skipped") && Catch::Contains("no .exr stacks"));
}

TEST_CASE("a capture named without a folder, run in its folder, globs the current folder", "[cli][capture]") {
  // `skypol import capture.toml` from the capture's folder: the frames' glob has no folder part
  // either, so the folder to list is the current one ("."), not the empty path.
  TempDir dir;
  setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
  const std::string in_dir = "cd '" + dir.path.string() + "' && " + skypol::test::skypol_bin();
  const Result r = skypol::test::run_shell(in_dir + " import -q capture.toml -o out.exr");
  INFO(r.out);
  REQUIRE(r.code == 0);
  const Result info = run("info " + (dir.path / "out.exr").string());
  CHECK_THAT(info.out, Catch::Contains("2022-06-21T06:00:00Z") && Catch::Contains("2022-06-21T07:00:00Z"));
  // A glob that matches nothing there names the current folder.
  dir.write("nothing.toml", "[capture]\nframes = [\"g_*.npy\"]\n\n" + std::string(kCamera));
  const Result none = skypol::test::run_shell(in_dir + " import -q nothing.toml -o none.exr");
  CHECK(none.code == 2);
  CHECK_THAT(none.out, Catch::Contains("nothing.toml:2") && Catch::Contains("'g_*.npy' matches no file (in .)"));
  CHECK_FALSE(fs::exists(dir.path / "none.exr"));
}

TEST_CASE("capture file errors name the key", "[cli][capture]") {
  SECTION("no [capture]") {
    TempDir dir;
    expect_error(setup(dir, ""), dir, "capture.toml", "missing section [capture]");
  }
  SECTION("a glob that matches nothing") {
    TempDir dir;
    expect_error(setup(dir, "[capture]\nframes = [\"g_*.npy\"]\n"), dir, "capture.toml:2", "matches no file");
  }
  SECTION("an unknown key") {
    TempDir dir;
    expect_error(setup(dir, "[capture]\nframes = [\"f_*.npy\"]\nframe_rate = 3\n"), dir, "capture.toml:3", "frame_rate");
  }
  // [site] is read by the scene language's parser (scene::read_site): the same messages as a scene's.
  SECTION("a latitude out of range in [site]") {
    TempDir dir;
    expect_error(setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n[site]\nlatitude_deg = 95\nlongitude_deg = 5\n"), dir,
                 "capture.toml:4:16: error: key 'site.latitude_deg'", "value 95 out of range [-90, 90]");
  }
  SECTION("an unknown key in [site]") {
    TempDir dir;
    expect_error(setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n[site]\nlatitude_deg = 43\nlongitude_deg = 5\nheight = 3\n"),
                 dir, "capture.toml:6", "site.height");
  }
  SECTION("a heading, which is what estimate finds") {
    TempDir dir2;
    write_frame(dir2.path / "f_20220621T060000.npy", 500);
    const std::string capture = dir2.write("capture.toml", std::string("[capture]\nframes = [\"f_*.npy\"]\n") +
                                                               "[camera]\nmodel = \"equidistant\"\nwidth = 16\nheight = 12\n"
                                                               "fx = 4\nfov_deg = 180\nheading_deg = 10\n[sensor]\n");
    expect_error(capture, dir2, "heading_deg", "what `skypol estimate` finds");
  }
  SECTION("no [sensor]") {
    TempDir dir;
    write_frame(dir.path / "f_20220621T060000.npy", 500);
    const std::string capture = dir.write("capture.toml", "[capture]\nframes = [\"f_*.npy\"]\n[camera]\nmodel = \"equidistant\"\n"
                                                          "width = 16\nheight = 12\nfx = 4\nfov_deg = 180\n");
    expect_error(capture, dir, "capture.toml", "missing section [sensor]");
  }
}

TEST_CASE("frame errors name the frame's file", "[cli][capture]") {
  SECTION("a frame of the wrong size") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
    write_frame(dir.path / "f_20220621T080000.npy", 500, 10, 16);
    expect_error(capture, dir, "f_20220621T080000.npy", "is 16x10, the [camera] is 16x12");
  }
  SECTION("a value beyond the ADC's range") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
    write_frame(dir.path / "f_20220621T080000.npy", 4096);
    expect_error(capture, dir, "f_20220621T080000.npy", "holds 4096");
  }
  SECTION("an unsupported dtype") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
    std::ofstream(dir.path / "f_20220621T080000.npy", std::ios::binary)
        << std::string("\x93NUMPY\x01\x00", 8) << char(70) << char(0)
        << "{'descr': '<i4', 'fortran_order': False, 'shape': (12, 16), }                  \n";
    expect_error(capture, dir, "f_20220621T080000.npy", "dtype '<i4' is not supported");
  }
  SECTION("Fortran order") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
    std::ofstream(dir.path / "f_20220621T080000.npy", std::ios::binary)
        << std::string("\x93NUMPY\x01\x00", 8) << char(70) << char(0)
        << "{'descr': '<u2', 'fortran_order': True, 'shape': (12, 16), }                   \n";
    expect_error(capture, dir, "f_20220621T080000.npy", "Fortran order");
  }
  SECTION("a three-dimensional array") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
    std::vector<unsigned short> v(12 * 16 * 3, 1);
    REQUIRE(skypol::stack::write_npy((dir.path / "f_20220621T080000.npy").string(), {12, 16, 3}, v.data()));
    expect_error(capture, dir, "f_20220621T080000.npy", "two-dimensional");
  }
  SECTION("a file that is not a .npy") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
    std::ofstream(dir.path / "f_20220621T080000.npy") << "hello";
    expect_error(capture, dir, "f_20220621T080000.npy", "not a NumPy .npy file");
  }
}

TEST_CASE("time errors name the frame or the CSV line", "[cli][capture]") {
  SECTION("a name that does not match the format") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\ntime_format = \"x_%Y%m%d*\"\n");
    expect_error(capture, dir, "f_20220621T060000.npy", "does not match the time format");
  }
  SECTION("times out of order") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\ntimes = \"csv\"\ntimes_csv = \"t.csv\"\n");
    dir.write("t.csv", "file,time\nf_20220621T060000.npy,2022-06-21T07:00:00Z\nf_20220621T070000.npy,2022-06-21T06:00:00Z\n");
    expect_error(capture, dir, "f_20220621T070000.npy", "is not after the previous frame's");
  }
  SECTION("a CSV line without a comma, and a bad time") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\ntimes = \"csv\"\ntimes_csv = \"t.csv\"\n");
    dir.write("t.csv", "file,time\nf_20220621T060000.npy 2022-06-21T07:00:00Z\n");
    expect_error(capture, dir, "t.csv:2:1", "expected 'file,time'");
    dir.write("t.csv", "file,time\nf_20220621T060000.npy,2022-06-31T07:00:00Z\n");
    expect_error(capture, dir, "t.csv:2:", "2022-06-31");
  }
  SECTION("a frame missing from the CSV") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\ntimes = \"csv\"\ntimes_csv = \"t.csv\"\n");
    dir.write("t.csv", "f_20220621T060000.npy,2022-06-21T06:00:00Z\n");
    expect_error(capture, dir, "f_20220621T070000.npy", "not listed in");
  }
  SECTION("EXIF times from a file that has none") {
    TempDir dir;
    const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\ntimes = \"exif\"\n");
    expect_error(capture, dir, "f_20220621T060000.npy", "no EXIF DateTimeOriginal");
  }
}

TEST_CASE("times from names follow the zone, and fractions of a second", "[cli][capture]") {
  TempDir dir;
  write_frame(dir.path / "sky 2022-06-21 08.00.00.250 cam1.npy", 500);
  write_frame(dir.path / "sky 2022-06-21 09.30.00.750 cam1.npy", 500);
  const std::string capture = dir.write("capture.toml", std::string("[capture]\nframes = [\"sky *.npy\"]\n") +
                                                            "time_format = \"sky %Y-%m-%d %H.%M.%S cam1.npy\"\n"
                                                            "time_zone = \"[Europe/Paris]\"\n" + kCamera);
  const std::string out = (dir.path / "out.exr").string();
  const Result r = run("import -q " + capture + " -o " + out);
  INFO(r.out);
  REQUIRE(r.code == 0);
  // Paris is UTC+2 in June.
  const Result info = run("info " + out);
  CHECK_THAT(info.out, Catch::Contains("2022-06-21T06:00:00.250Z") && Catch::Contains("2022-06-21T07:30:00.750Z"));
}

TEST_CASE("export errors name the channel or the format", "[cli][capture]") {
  TempDir dir;
  const std::string capture = setup(dir, "[capture]\nframes = [\"f_*.npy\"]\n");
  const std::string stack = (dir.path / "s.exr").string();
  REQUIRE(run("import -q " + capture + " -o " + stack).code == 0);
  const std::string out = (dir.path / "x").string();
  Result r = run("export " + stack + " -c raw -o " + out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("has no channel 'raw'"));
  r = run("export " + stack + " -f png -c S0 -o " + out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("'S0.Y' is a radiance"));
  r = run("export " + stack + " -f jpeg -o " + out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("expected exr, tiff, npy or png"));
  r = run("export " + stack + " --band Q -o " + out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("--band 'Q'"));
  CHECK_FALSE(fs::exists(out));
}
