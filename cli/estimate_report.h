// Estimate north on a stack and print the estimate beside the truth in its headers.
#pragma once

#include <string>

namespace skypol::cli {

// Prints a table (or JSON) for `method` on the stack at `path`. Throws on bad input.
void print_estimate(const std::string& path, const std::string& method, bool json);

}  // namespace skypol::cli
