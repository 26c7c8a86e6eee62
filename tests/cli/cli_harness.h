// Running the skypol executable from a test: its exit code and output, in a temporary folder.
#pragma once

#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace skypol::test {

// The [site] of the test scenes: the SkyPole paper's, Marseille (a scene text's first lines).
inline constexpr const char* kMarseilleSite = "[site]\nlatitude_deg = 43.28699\nlongitude_deg = 5.40336\n";

struct Result {
  int code;
  std::string out;  // stdout and stderr together
};

// Any shell command, its exit code and its output (stdout and stderr together).
inline Result run_shell(const std::string& command) {
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  REQUIRE(p != nullptr);
  std::string out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p)) out += buf.data();
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// The skypol executable under test (ctest sets SKYPOL_BIN).
inline std::string skypol_bin() {
  const char* bin = std::getenv("SKYPOL_BIN");
  REQUIRE(bin != nullptr);
  return bin;
}

// The skypol executable under test with these arguments.
inline Result run(const std::string& args) { return run_shell(skypol_bin() + " " + args); }

struct TempDir {
  std::filesystem::path path;
  TempDir() {
    static int count = 0;  // several folders in one test process stay apart
    path = std::filesystem::temp_directory_path() /
           ("skypol-cli-" + std::to_string(::getpid()) + "-" + std::to_string(count++));
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

}  // namespace skypol::test
