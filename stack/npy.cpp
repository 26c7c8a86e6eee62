#include "stack/npy.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <regex>
#include <stdexcept>

namespace skypol::stack {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::invalid_argument(path + ": " + what);
}

std::size_t element_size(const std::string& descr) {
  if (descr == "<u1" || descr == "|u1") return 1;
  if (descr == "<u2") return 2;
  if (descr == "<f4") return 4;
  if (descr == "<f8") return 8;
  return 0;
}

// The header is a Python dict literal: {'descr': '<u2', 'fortran_order': False, 'shape': (2048, 2448), }
std::string dict_value(const std::string& header, const std::string& key, const std::string& path) {
  const std::regex re("['\"]" + key + "['\"]\\s*:\\s*('[^']*'|\"[^\"]*\"|True|False|\\([^)]*\\))");
  std::smatch m;
  if (!std::regex_search(header, m, re)) fail(path, "the .npy header has no '" + key + "' (header: " + header + ")");
  return m[1].str();
}

template <class T>
bool write_typed(const std::string& path, const std::vector<std::size_t>& shape, const T* values, const char* descr) {
  std::string dims;
  std::size_t n = 1;
  for (std::size_t d : shape) {
    dims += std::to_string(d) + ",";
    n *= d;
  }
  if (shape.size() > 1) dims.pop_back();  // (5,) for one dimension, (2, 3) otherwise
  std::string header = std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': (" + dims + "), }";
  // Magic (6) + version (2) + length (2) + header + '\n', padded with spaces to a multiple of 64.
  const std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  std::ofstream out(path, std::ios::binary);
  const unsigned char prefix[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
  out.write(reinterpret_cast<const char*>(prefix), 8);
  const std::uint16_t len = static_cast<std::uint16_t>(header.size());
  const unsigned char le[2] = {static_cast<unsigned char>(len & 0xff), static_cast<unsigned char>(len >> 8)};
  out.write(reinterpret_cast<const char*>(le), 2);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  // x86 and ARM Linux are little-endian, as '<' says.
  out.write(reinterpret_cast<const char*>(values), static_cast<std::streamsize>(n * sizeof(T)));
  out.close();
  return static_cast<bool>(out);
}

}  // namespace

NpyArray read_npy(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open (" + std::string(std::strerror(errno)) + ")");
  unsigned char prefix[8] = {};
  in.read(reinterpret_cast<char*>(prefix), 8);
  if (!in || std::memcmp(prefix, "\x93NUMPY", 6) != 0) fail(path, "not a NumPy .npy file (no \\x93NUMPY magic)");
  const int major = prefix[6];
  if (major < 1 || major > 3) fail(path, "unsupported .npy format version " + std::to_string(major));
  std::size_t header_len = 0;
  if (major == 1) {
    unsigned char b[2];
    in.read(reinterpret_cast<char*>(b), 2);
    header_len = b[0] | (static_cast<std::size_t>(b[1]) << 8);
  } else {
    unsigned char b[4];
    in.read(reinterpret_cast<char*>(b), 4);
    header_len = b[0] | (static_cast<std::size_t>(b[1]) << 8) | (static_cast<std::size_t>(b[2]) << 16) |
                 (static_cast<std::size_t>(b[3]) << 24);
  }
  if (!in || header_len > (1u << 20)) fail(path, "truncated or corrupt .npy header");
  std::string header(header_len, '\0');
  in.read(header.data(), static_cast<std::streamsize>(header_len));
  if (!in) fail(path, "truncated .npy header");

  NpyArray a;
  a.descr = dict_value(header, "descr", path);
  a.descr = a.descr.substr(1, a.descr.size() - 2);
  const std::size_t size = element_size(a.descr);
  if (size == 0) {
    fail(path, "dtype '" + a.descr + "' is not supported (expected <u1, <u2, <f4 or <f8: uint8, little-endian uint16, "
               "float32 or float64)");
  }
  if (dict_value(header, "fortran_order", path) != "False") {
    fail(path, "the array is in Fortran order (save it with numpy.ascontiguousarray first)");
  }
  const std::string shape = dict_value(header, "shape", path);
  std::size_t n = 1;
  const std::regex dim("\\d+");
  for (auto it = std::sregex_iterator(shape.begin(), shape.end(), dim); it != std::sregex_iterator(); ++it) {
    a.shape.push_back(std::stoull(it->str()));
    n *= a.shape.back();
  }
  if (a.shape.empty()) fail(path, "the array has no dimensions (a scalar)");

  std::vector<unsigned char> bytes(n * size);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::size_t>(in.gcount()) != bytes.size()) {
    fail(path, "the file is shorter than its shape says (" + std::to_string(n) + " elements of " + a.descr + ")");
  }
  a.values.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char* p = bytes.data() + i * size;
    if (size == 1) {
      a.values[i] = p[0];
    } else if (size == 2) {
      a.values[i] = p[0] | (p[1] << 8);
    } else if (size == 4) {
      float f;
      std::memcpy(&f, p, 4);
      a.values[i] = f;
    } else {
      std::memcpy(&a.values[i], p, 8);
    }
  }
  return a;
}

bool write_npy(const std::string& path, const std::vector<std::size_t>& shape, const float* values) {
  return write_typed(path, shape, values, "<f4");
}

bool write_npy(const std::string& path, const std::vector<std::size_t>& shape, const unsigned short* values) {
  return write_typed(path, shape, values, "<u2");
}

}  // namespace skypol::stack
