// The [output] section's storage keys: pixel type, compression, zip level, and the opt-in that a
// lossy compression on Stokes channels needs (the losses are measured by `skypol tradeoff
// compression`, docs/benchmarks.md). Each error class is located at its key.
#include <catch2/catch.hpp>

#include "scene/scene.h"

using skypol::scene::parse_scene;
using skypol::scene::SceneError;

namespace {

// [output] starts on line 12, so its first key is on line 13.
const std::string kHead = R"([site]
latitude_deg = 43.28699
longitude_deg = 5.40336

[time]
instants = ["2022-09-23T10:00:00Z"]

[camera]
fx = 20
width = 64
height = 48
[output]
)";

std::string error_of(const std::string& output_keys) {
  try {
    parse_scene(kHead + output_keys, "out.toml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("storage keys are read as written, and absent ones take the documented defaults", "[scene][output]") {
  const auto none = parse_scene(kHead.substr(0, kHead.find("[output]")), "plain.toml");
  // docs/scenes.md: half, zip at OpenEXR's default level.
  CHECK(none.output.half);
  CHECK(none.output.compression == "zip");
  CHECK(parse_scene(kHead + "path = \"a.exr\"\n", "o.toml").output.half);  // a section that leaves it out
  CHECK(none.output.zip_level == 0);
  CHECK_FALSE(none.output.allow_lossy);
  CHECK(none.output.path == "out/plain.exr");
  const auto s = parse_scene(kHead + "pixel_type = \"float\"\ncompression = \"zips\"\nzip_level = 9\n", "o.toml");
  CHECK_FALSE(s.output.half);
  CHECK(s.output.compression == "zips");
  CHECK(s.output.zip_level == 9);
  CHECK(parse_scene(kHead + "pixel_type = \"half\"\ncompression = \"piz\"\n", "o.toml").output.half);
}

TEST_CASE("a lossy compression on Stokes channels is refused without allow_lossy, naming the loss", "[scene][output][errors]") {
  // b44 and b44a pack half channels; float ones they store as they are.
  for (const char* c : {"b44", "b44a"}) {
    const std::string e = error_of(std::string("pixel_type = \"half\"\ncompression = \"") + c + "\"\n");
    CHECK_THAT(e, Catch::StartsWith("out.toml:14:") && Catch::Contains("output.compression") &&
                      Catch::Contains("lossy") && Catch::Contains("AoLP errors up to") &&
                      Catch::Contains("allow_lossy = true"));
    CHECK(parse_scene(kHead + "pixel_type = \"float\"\ncompression = \"" + c + "\"\n", "o.toml").output.compression == c);
  }
  // DWA quantizes *.Y channels whatever their type.
  for (const char* type : {"float", "half"})
    for (const char* c : {"dwaa", "dwab"})
      CHECK_THAT(error_of(std::string("pixel_type = \"") + type + "\"\ncompression = \"" + c + "\"\n"),
                 Catch::StartsWith("out.toml:14:") && Catch::Contains("lossy") && Catch::Contains("AoLP errors up to"));
  // pxr24 rounds float to 24 bits and leaves half alone.
  CHECK_THAT(error_of("compression = \"pxr24\"\npixel_type = \"float\"\n"),
             Catch::StartsWith("out.toml:13:") && Catch::Contains("lossy") && Catch::Contains("24 bits"));
  CHECK(parse_scene(kHead + "pixel_type = \"half\"\ncompression = \"pxr24\"\n", "o.toml").output.compression == "pxr24");
}

TEST_CASE("allow_lossy = true accepts a lossy compression; mask-only stacks need no opt-in", "[scene][output]") {
  const auto s = parse_scene(kHead + "pixel_type = \"half\"\ncompression = \"b44\"\nallow_lossy = true\n", "o.toml");
  CHECK(s.output.allow_lossy);
  CHECK(s.output.compression == "b44");
  // DWA keeps a channel named "mask" lossless: no Stokes values to lose.
  CHECK(parse_scene(kHead + "channels = [\"mask\"]\ncompression = \"dwaa\"\n", "o.toml").output.compression == "dwaa");
}

TEST_CASE("zip_level errors: out of range, or beside a compression that has no deflate level", "[scene][output][errors]") {
  CHECK_THAT(error_of("compression = \"zip\"\nzip_level = 10\n"),
             Catch::StartsWith("out.toml:14:") && Catch::Contains("output.zip_level"));
  CHECK_THAT(error_of("compression = \"zip\"\nzip_level = 0\n"), Catch::Contains("output.zip_level"));
  CHECK_THAT(error_of("compression = \"piz\"\nzip_level = 4\n"),
             Catch::StartsWith("out.toml:14:") && Catch::Contains("output.zip_level") &&
                 Catch::Contains("deflate level of zip and zips"));
  CHECK_THAT(error_of("compression = \"lzma\"\n"),
             Catch::StartsWith("out.toml:13:") && Catch::Contains("output.compression") && Catch::Contains("dwab"));
  CHECK_THAT(error_of("allow_lossy = \"yes\"\n"), Catch::Contains("output.allow_lossy"));
}
