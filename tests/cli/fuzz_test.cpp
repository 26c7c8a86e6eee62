// A seeded fuzzer of the executable (issue "hardening"): mutants of the shipped scenes (keys
// deleted, duplicated, renamed or retyped, numbers out of range, NaN and inf literals, huge
// strings, bad dates, includes to nowhere, truncation) and of a small stack file (truncated,
// bytes flipped, attributes dropped). Each mutant is rendered small (--set camera.binning=32),
// or read by info, estimate and preview. What must hold for every one:
//   - the exit status is 0 or 2 (never 3, never a crash);
//   - an error is located: "FILE:LINE:COL: error:" or at least "FILE: error:", FILE the input;
//   - a failure leaves nothing behind (no output, no temporary);
//   - a file written holds no NaN or Inf (read back with the stack reader).
// SKYPOL_FUZZ_SEED picks another seed, SKYPOL_FUZZ_SCENES / SKYPOL_FUZZ_STACKS other counts
// (defaults 300 and 40: with OpenImageIO out of the start-up a run of skypol costs milliseconds
// beyond its tiny render, so the suite's share is ~30 s on 2 cores; a longer hunt sets them
// higher); a failing mutant is printed whole so that it can be replayed by hand.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "cli/cli_harness.h"
#include "stack/stack_io.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::uint32_t env_or(const char* name, std::uint32_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? static_cast<std::uint32_t>(std::stoul(v)) : fallback;
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream is(text);
  for (std::string line; std::getline(is, line);) out.push_back(line);
  return out;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

bool is_assignment(const std::string& line) {
  const auto eq = line.find('=');
  return eq != std::string::npos && eq > 0 && line[0] != '#' && line[0] != '[';
}

template <class T>
const T& pick(std::mt19937& rng, const std::vector<T>& v) {
  return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
}

// One mutation of a scene's text.
std::string mutate_scene(std::string text, std::mt19937& rng) {
  std::vector<std::string> lines = lines_of(text);
  std::vector<std::size_t> keys;
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (is_assignment(lines[i])) keys.push_back(i);
  const int op = std::uniform_int_distribution<int>(0, 11)(rng);
  if (op == 10) return "include = \"nowhere/none.toml\"\n" + text;
  if (op == 11) return text.substr(0, std::uniform_int_distribution<std::size_t>(0, text.size())(rng));
  if (keys.empty()) return text + "\nextra = 1\n";
  const std::size_t at = pick(rng, keys);
  std::string& line = lines[at];
  const auto eq = line.find('=');
  const std::string key = line.substr(0, eq);
  static const std::vector<std::string> numbers{"nan", "inf", "-inf", "+nan", "1e308", "-1e308", "-1", "0",
                                                "9223372036854775807", "-9223372036854775808", "1e-320", "0.5",
                                                "123456789", "-0.0"};
  static const std::vector<std::string> other_types{"\"text\"", "true", "[1, 2]", "{ a = 1 }", "1979-05-27",
                                                    "07:32:00", "[]", "[\"a\", 1]", "\"\""};
  static const std::vector<std::string> dates{"\"2022-02-30T10:00:00Z\"", "\"2022-13-01T00:00:00Z\"",
                                              "\"2022-09-23T25:00:00Z\"", "\"2022-09-23T08:00:00\"",
                                              "\"not a date\"", "\"99999-01-01T00:00:00Z\"", "\"2022-09-23\"",
                                              "2022-09-23T08:00:00", "\"-2022-09-23T08:00:00Z\""};
  switch (op) {
    case 0: lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(at)); break;
    case 1: lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at), line); break;
    case 2: line = key + "= " + pick(rng, other_types); break;
    case 3:
    case 4: line = key + "= " + pick(rng, numbers); break;
    case 5: line = key + "= \"" + std::string(std::uniform_int_distribution<int>(200, 20000)(rng), 'x') + "\""; break;
    case 6: line = key + "= " + pick(rng, dates); break;
    case 7: line = key.substr(0, key.find_last_not_of(' ') + 1) + "x = " + line.substr(eq + 1); break;
    case 8: line = key + "= [" + line.substr(eq + 1) + ", " + pick(rng, numbers) + "]"; break;
    default: {  // a section header deleted or doubled
      std::vector<std::size_t> headers;
      for (std::size_t i = 0; i < lines.size(); ++i)
        if (!lines[i].empty() && lines[i][0] == '[') headers.push_back(i);
      if (headers.empty()) break;
      const std::size_t h = pick(rng, headers);
      if (rng() % 2) {
        lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(h));
      } else {
        lines.push_back(lines[h]);
      }
    }
  }
  return joined(lines);
}

// A scene error: an input's name (the scene, a file it includes, --set) with :LINE:COL, then
// ": error: ", as docs/scenes.md promises for every error.
bool located(const std::string& out, const std::vector<std::string>& inputs) {
  for (const std::string& in : inputs) {
    for (std::size_t at = out.find(in); at != std::string::npos; at = out.find(in, at + 1)) {
      static const std::regex loc("^[^: \n]*:[0-9]+:[0-9]+: error: ");
      if (std::regex_search(out.substr(at + in.size(), 400), loc)) return true;
    }
  }
  return false;
}

// Every value of every channel of a stack is finite.
void require_finite_stack(const std::string& path) {
  const skypol::stack::Stack st = skypol::stack::read_stack(path);
  for (const skypol::stack::Frame& f : st.frames) {
    for (const auto& [name, values] : f.channels) {
      INFO(path << " channel " << name);
      REQUIRE(std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); }));
    }
  }
}

std::set<std::string> names_in(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
  return out;
}

}  // namespace

TEST_CASE("fuzz: mutants of the shipped scenes exit 0 or 2, located, leaving nothing or a finite stack",
          "[cli][fuzz]") {
  const std::uint32_t seed = env_or("SKYPOL_FUZZ_SEED", 20261201);
  const std::uint32_t count = env_or("SKYPOL_FUZZ_SCENES", 300);
  std::mt19937 rng(seed);
  const fs::path shipped = fs::path(SKYPOL_SOURCE_DIR) / "scenes";
  std::vector<std::pair<std::string, std::string>> scenes;
  for (const auto& e : fs::directory_iterator(shipped)) {
    if (e.path().extension() == ".toml") scenes.emplace_back(e.path().filename().string(), read_all(e.path()));
  }
  std::sort(scenes.begin(), scenes.end());
  REQUIRE(scenes.size() >= 5);
  // The mutant sits among the shipped scenes (their includes resolve), output goes elsewhere.
  TempDir dir;
  for (const auto& e : fs::directory_iterator(shipped)) fs::create_symlink(e.path(), dir.path / e.path().filename());
  const fs::path out_dir = dir.path / "out";
  const std::set<std::string> inputs = names_in(dir.path);
  int ok = 0, refused = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const auto& [name, text] = pick(rng, scenes);
    std::string mutant = mutate_scene(text, rng);
    if (rng() % 3 == 0) mutant = mutate_scene(mutant, rng);
    const std::string m = (dir.path / "m.toml").string();
    std::ofstream(m, std::ios::binary | std::ios::trunc) << mutant;
    fs::create_directories(out_dir);
    const std::string out = (out_dir / "o.exr").string();
    const Result r = run("render -q " + m + " -o " + out + " --set camera.binning=32");
    INFO("seed " << seed << " mutant " << i << " of " << name << ":\n" << mutant.substr(0, 3000));
    INFO("output: " << r.out.substr(0, 2000));
    REQUIRE((r.code == 0 || r.code == 2));
    if (r.code == 0) {
      ++ok;
      REQUIRE(fs::is_regular_file(out));
      for (const std::string& f : names_in(out_dir)) REQUIRE((f == "o.exr" || f == "o-preview"));
      require_finite_stack(out);
    } else {
      ++refused;
      REQUIRE(located(r.out, {m, dir.path.string() + "/", "--set"}));
      REQUIRE(names_in(out_dir).empty());
    }
    fs::remove(m);
    REQUIRE(names_in(dir.path) == [&] {
      std::set<std::string> s = inputs;
      s.insert("out");
      return s;
    }());
    fs::remove_all(out_dir);
  }
  // The mutations are not all harmless, nor all fatal.
  CHECK(ok > 0);
  CHECK(refused > 0);
}

TEST_CASE("fuzz: mutants of a stack file are read, estimated and previewed with exit 0 or 2", "[cli][fuzz]") {
  const std::uint32_t seed = env_or("SKYPOL_FUZZ_SEED", 20261201);
  const std::uint32_t count = env_or("SKYPOL_FUZZ_STACKS", 40);
  std::mt19937 rng(seed + 1);
  TempDir dir;
  const std::string scene = dir.write("small.toml", R"([site]
latitude_deg = -33.86
longitude_deg = 151.21
[time]
instants = ["2023-01-10T01:00:00Z", "2023-01-10T03:00:00Z"]
[camera]
model = "equidistant"
fx = 12
width = 40
height = 36
fov_deg = 185
[output]
compression = "none"
)");
  const std::string good = (dir.path / "good.exr").string();
  REQUIRE(run("render -q " + scene + " -o " + good).code == 0);
  const std::string bytes = read_all(good);
  static const std::vector<std::string> attributes{"skypol:camera", "skypol:bands", "skypol:unixTime",
                                                   "skypol:poleENU", "skypol:worldFromCamera", "channels",
                                                   "dataWindow", "skypol:sunDirectionENU", "compression"};
  const fs::path work = dir.path / "w";
  for (std::uint32_t i = 0; i < count; ++i) {
    std::string m = bytes;
    const int op = std::uniform_int_distribution<int>(0, 2)(rng);
    if (op == 0) {
      m.resize(std::uniform_int_distribution<std::size_t>(0, m.size() - 1)(rng));
    } else if (op == 1) {
      const int flips = std::uniform_int_distribution<int>(1, 8)(rng);
      for (int k = 0; k < flips; ++k) {
        m[std::uniform_int_distribution<std::size_t>(0, m.size() - 1)(rng)] ^=
            static_cast<char>(1 << std::uniform_int_distribution<int>(0, 7)(rng));
      }
    } else {  // an attribute's name changed in place: the attribute is gone
      const std::string& a = pick(rng, attributes);
      for (std::size_t at = m.find(a + '\0'); at != std::string::npos; at = m.find(a + '\0', at + 1)) m[at + a.size() - 1] ^= 0x20;
    }
    fs::create_directories(work);
    const std::string s = (work / "s.exr").string();
    std::ofstream(s, std::ios::binary) << m;
    INFO("seed " << seed << " stack mutant " << i << " (operation " << op << ")");
    for (const std::string& args : {"info " + s, "estimate " + s, "preview " + s + " -o " + (work / "pv").string()}) {
      const Result r = run(args);
      INFO(args << "\n" << r.out.substr(0, 2000));
      REQUIRE((r.code == 0 || r.code == 2));
      if (r.code == 2) REQUIRE_THAT(r.out, Catch::Contains(s) && Catch::Contains("error: "));
      std::set<std::string> left = names_in(work);
      if (args.rfind("preview", 0) == 0 && r.code == 0) {
        REQUIRE(left.count("pv") == 1);
        left.erase("pv");
      }
      REQUIRE(left == std::set<std::string>{"s.exr"});
    }
    fs::remove_all(work);
  }
}
