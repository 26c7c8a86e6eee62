// NumPy .npy files (format versions 1–3, numpy.lib.format): the arrays the Marseille skylight
// database and most Python pipelines save. Reading accepts little-endian uint8, uint16, float32 and
// float64 ('<u1' or '|u1', '<u2', '<f4', '<f8') in C order; anything else is an error that names
// the file and what it found. Writing produces version 1.0 files that numpy.load reads.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace skypol::stack {

struct NpyArray {
  std::string descr;                // as in the file, e.g. "<u2"
  std::vector<std::size_t> shape;   // e.g. {rows, cols}
  std::vector<double> values;       // every element, in C order (exact for the accepted types)
};

// Throws std::invalid_argument "PATH: ..." for a missing file, a bad header, an unsupported
// dtype, Fortran order or a short file.
NpyArray read_npy(const std::string& path);

// A C-order array of float32 ('<f4') or uint16 ('<u2') values (written whole to `path`; the
// caller picks a temporary name). Returns false on an I/O error.
bool write_npy(const std::string& path, const std::vector<std::size_t>& shape, const float* values);
bool write_npy(const std::string& path, const std::vector<std::size_t>& shape, const unsigned short* values);

}  // namespace skypol::stack
