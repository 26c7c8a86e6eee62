// `skypol reproduce`: bad input is refused with a message that names it and exit code 2 (or
// CLI11's for an unknown paper), and nothing is written. The reduced run's values are checked by
// the ctest cli/reproduce_small (scripts/reproduce --small --check).
#include <catch2/catch.hpp>

#include <filesystem>

#include "cli/cli_harness.h"

using skypol::test::run;
using skypol::test::TempDir;

TEST_CASE("reproduce refuses an unknown paper, a missing scene and an unwritable folder", "[cli]") {
  TempDir dir;
  const std::string out = (dir.path / "out").string();
  auto r = run("reproduce nature2024 --out " + out);
  INFO(r.out);
  CHECK(r.code != 0);
  CHECK_THAT(r.out, Catch::Contains("nature2024"));
  CHECK_FALSE(std::filesystem::exists(out));

  r = run("reproduce skypole --small -q --out " + out + " --scene " + (dir.path / "missing.toml").string());
  INFO(r.out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("missing.toml"));
  CHECK_FALSE(std::filesystem::exists(std::filesystem::path(out) / "skypole_protocol.csv"));

  // A file where the folder should be.
  const std::string file = dir.write("not_a_folder", "x");
  r = run("reproduce sun2019 --small -q --out " + file);
  INFO(r.out);
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("not_a_folder"));
}
