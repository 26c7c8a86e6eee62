// `skypol sweep` as users run it: a whole sweep, resume, shards that add up to the sweep, and the
// two runner scripts of docs/datasets.md on scenes/sweeps/tiny.toml — scripts/sweep-parallel run
// with GNU parallel, scripts/sweep-slurm.sbatch checked for syntax, its #SBATCH lines parsed, and
// run as one array task would be.
#include <catch2/catch.hpp>

#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "cli/cli_harness.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string kSource = SKYPOL_SOURCE_DIR;
const std::string kTiny = kSource + "/scenes/sweeps/tiny.toml";

// A shell command (not skypol), with SKYPOL pointing at the executable under test.
Result sh(const std::string& command) {
  return skypol::test::run_shell("SKYPOL='" + skypol::test::skypol_bin() + "' " + command);
}

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The stack names a manifest lists.
std::set<std::string> manifest_files(const fs::path& dir) {
  std::set<std::string> files;
  for (const std::string& line : lines_of(dir / "manifest.jsonl")) {
    const auto at = line.find("\"file\": \"") + 9;
    files.insert(line.substr(at, line.find('"', at) - at));
  }
  return files;
}

std::set<std::string> stacks_in(const fs::path& dir) {
  std::set<std::string> files;
  if (!fs::exists(dir)) return files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".exr") files.insert(e.path().filename().string());
  }
  return files;
}

}  // namespace

TEST_CASE("sweep renders a shard, then resumes with the rest, all in the manifest", "[cli][sweep]") {
  TempDir dir;
  const fs::path out = dir.path / "tiny";
  const Result first = run("sweep " + kTiny + " -o " + out.string() + " --shard 1/4");
  INFO(first.out);
  REQUIRE(first.code == 0);
  // Variants 0..5 round-robin over 4 shards: shard 1 has 0 and 4.
  CHECK_THAT(first.out, Catch::Contains("6 variant(s), shard 1/4 has 2: 2 rendered, 0 already complete, 0 failed"));
  const std::set<std::string> listed = manifest_files(out);
  CHECK(listed.size() == 6);  // the manifest lists the whole sweep from the first run
  CHECK(stacks_in(out).size() == 2);
  const Result rest = run("sweep " + kTiny + " -o " + out.string());
  INFO(rest.out);
  CHECK_THAT(rest.out, Catch::Contains("shard 1/1 has 6: 4 rendered, 2 already complete, 0 failed"));
  CHECK(stacks_in(out) == listed);
  // A stack's own headers agree with its manifest line: variant 4 is latitude 45, heading 120.
  const std::vector<std::string> manifest = lines_of(out / "manifest.jsonl");
  CHECK_THAT(manifest[4], Catch::Contains("\"params\": {\"site.latitude_deg\": 45, \"camera.heading_deg\": 120}"));
  const std::string file = manifest[4].substr(manifest[4].find("\"file\": \"") + 9, 19);
  const Result info = run("info " + (out / file).string());
  CHECK_THAT(info.out, Catch::Contains("6 frame(s), 153x128 px"));
  CHECK_THAT(info.out, Catch::Contains("2022-09-23T06:00:00Z    45.00000"));
}

TEST_CASE("scripts/sweep-parallel renders a sweep with GNU parallel", "[cli][sweep][scripts]") {
  TempDir dir;
  const fs::path out = dir.path / "tiny";
  const Result r = sh("JOBS=2 THREADS=1 SHARDS=2 " + kSource + "/scripts/sweep-parallel " + kTiny + " " + out.string());
  INFO(r.out);
  REQUIRE(r.code == 0);
  CHECK(stacks_in(out) == manifest_files(out));
  CHECK(stacks_in(out).size() == 6);
  CHECK_THAT(r.out, Catch::Contains("0 rendered, 6 already complete, 0 failed"));  // the closing check
  CHECK_THAT(r.out, Catch::Contains("sweep-parallel: 2 shard(s), 2 at once x 1 thread(s):"));
  // Its extra arguments reach skypol intact, and a bad sweep stops it before any shard runs.
  const Result bad = sh(kSource + "/scripts/sweep-parallel " + kTiny + " " + (dir.path / "bad").string() +
                        " --set 'camera.heading_deg=30'");
  CHECK(bad.code == 2);
  CHECK_THAT(bad.out, Catch::Contains("--set:1:1: error: key 'camera.heading_deg': the command line's --set cannot set a sweep axis"));
  CHECK_FALSE(fs::exists(dir.path / "bad"));
}

TEST_CASE("scripts/sweep-slurm.sbatch is valid bash with well-formed #SBATCH lines", "[cli][sweep][scripts]") {
  const std::string script = kSource + "/scripts/sweep-slurm.sbatch";
  CHECK(sh("bash -n " + script).code == 0);
  std::ifstream in(script);
  std::vector<std::string> directives;
  bool commands_started = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("#SBATCH", 0) == 0) {
      // sbatch stops reading directives at the first command: every one must come before it.
      CHECK_FALSE(commands_started);
      directives.push_back(line);
    } else if (!line.empty() && line[0] != '#') {
      commands_started = true;
    }
  }
  const std::regex form(R"(#SBATCH --([a-z-]+)=(\S+))");
  const std::map<std::string, std::regex> value{
      {"job-name", std::regex(R"([A-Za-z0-9_.-]+)")},
      {"array", std::regex(R"(\d+-\d+(%\d+)?)")},
      {"cpus-per-task", std::regex(R"([1-9]\d*)")},
      {"mem-per-cpu", std::regex(R"(\d+[KMGT]?)")},
      {"time", std::regex(R"((\d+-)?\d{1,2}:\d{2}:\d{2})")},
      {"output", std::regex(R"([A-Za-z0-9_.%/-]+)")},
  };
  std::set<std::string> seen;
  for (const std::string& d : directives) {
    INFO(d);
    std::smatch m;
    REQUIRE(std::regex_match(d, m, form));
    REQUIRE(value.count(m[1]) == 1);
    CHECK(std::regex_match(m[2].str(), value.at(m[1])));
    CHECK(seen.insert(m[1]).second);
  }
  CHECK(seen.count("array") == 1);
  CHECK(seen.count("cpus-per-task") == 1);
}

TEST_CASE("scripts/sweep-slurm.sbatch runs one shard as an array task would", "[cli][sweep][scripts]") {
  TempDir dir;
  const fs::path out = dir.path / "tiny";
  // Task 11 of an array 10-12 is shard 2/3: variants 1 and 4.
  const std::string env = "SLURM_ARRAY_TASK_ID=11 SLURM_ARRAY_TASK_MIN=10 SLURM_ARRAY_TASK_MAX=12 "
                          "SLURM_ARRAY_TASK_COUNT=3 SLURM_CPUS_PER_TASK=1 ";
  const Result r = sh(env + "bash " + kSource + "/scripts/sweep-slurm.sbatch " + kTiny + " " + out.string());
  INFO(r.out);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.out, Catch::Contains("shard 2/3 has 2: 2 rendered"));
  const std::set<std::string> stacks = stacks_in(out);
  REQUIRE(stacks.size() == 2);
  CHECK(stacks.begin()->substr(0, 6) == "000001");
  CHECK(std::next(stacks.begin())->substr(0, 6) == "000004");
  // Outside an array it refuses, writing nothing.
  const Result alone = sh("bash " + kSource + "/scripts/sweep-slurm.sbatch " + kTiny + " " + (dir.path / "x").string());
  CHECK(alone.code != 0);
  CHECK_THAT(alone.out, Catch::Contains("not an array task"));
  CHECK_FALSE(fs::exists(dir.path / "x"));
}
