// Scratch folders and whole-file reads for the tests that write files and compare their bytes.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace skypol::test {

// A folder of this process's own under the system's temporary folder, created if absent: tests
// run in parallel under ctest, so `tag` and the process id keep them apart.
inline std::filesystem::path temp_dir(const std::string& tag) {
  std::filesystem::path d = std::filesystem::temp_directory_path() / (tag + "-" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

// Every byte of a file ("" if it cannot be opened).
inline std::string file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace skypol::test
