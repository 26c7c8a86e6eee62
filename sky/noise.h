// Seeded 3-D value noise, for procedural sky effects such as clouds (which sum octaves of it).
// Deterministic: the same seed and point give the same value on every platform (our own integer
// generator and Fisher–Yates shuffle, no std:: distributions, whose results vary by library).
#pragma once

#include <array>
#include <cstdint>

namespace skypol::sky::detail {

class ValueNoise {
 public:
  explicit ValueNoise(std::uint64_t seed);

  // Value noise at (x, y, z): a pseudo-random value per integer lattice point, blended with the
  // quintic fade (C² continuous, no creases at cell borders). Range [0, 1). Period 256 cells.
  float operator()(float x, float y, float z) const;

 private:
  float lattice(int i, int j, int k) const {
    return values_[perm_[(perm_[(perm_[i & 255] + j) & 255] + k) & 255]];
  }

  std::array<std::uint8_t, 256> perm_{};
  std::array<float, 256> values_{};
};

}  // namespace skypol::sky::detail
