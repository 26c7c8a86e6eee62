// One image of named float channels as a single-part OpenEXR file: the arrays behind a report's
// figures (skypol reproduce), readable by any EXR reader (OpenImageIO, numpy via OIIO). Not a
// stack: no truth in the header, only the channels and a free-text comment.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace skypol::stack {

// Every channel must hold width·height values (row-major); non-finite values are written as 0
// (no NaN or Inf reaches a file). Channel names are sorted by OpenEXR. Written under a temporary
// name and renamed when complete. Throws std::invalid_argument for a size mismatch or no
// channels, std::runtime_error naming the path for an I/O problem.
void write_image_exr(const std::string& path, int width, int height,
                     const std::map<std::string, std::vector<float>>& channels,
                     const std::string& comment = "");

}  // namespace skypol::stack
