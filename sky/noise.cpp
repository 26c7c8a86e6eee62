// Value noise from a seeded permutation table (Perlin's hashing scheme: three table look-ups
// per lattice point, no multiplications), filled by a splitmix64 stream.
#include "sky/noise.h"

#include <cmath>
#include <cstddef>

namespace skypol::sky::detail {
namespace {

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
float lerp(float a, float b, float t) { return a + (b - a) * t; }

}  // namespace

ValueNoise::ValueNoise(std::uint64_t seed) {
  std::uint64_t state = seed;
  for (std::size_t i = 0; i < 256; ++i) {
    perm_[i] = static_cast<std::uint8_t>(i);
    values_[i] = static_cast<float>(splitmix64(state) >> 40) * (1.0f / 16777216.0f);  // 24 bits → [0, 1)
  }
  for (std::size_t i = 255; i > 0; --i) {  // Fisher–Yates with our own generator
    const std::size_t j = static_cast<std::size_t>(splitmix64(state) % (i + 1));
    const std::uint8_t t = perm_[i];
    perm_[i] = perm_[j];
    perm_[j] = t;
  }
}

float ValueNoise::operator()(float x, float y, float z) const {
  const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const int i = static_cast<int>(fx), j = static_cast<int>(fy), k = static_cast<int>(fz);
  const float u = fade(x - fx), v = fade(y - fy), w = fade(z - fz);
  const float c00 = lerp(lattice(i, j, k), lattice(i + 1, j, k), u);
  const float c10 = lerp(lattice(i, j + 1, k), lattice(i + 1, j + 1, k), u);
  const float c01 = lerp(lattice(i, j, k + 1), lattice(i + 1, j, k + 1), u);
  const float c11 = lerp(lattice(i, j + 1, k + 1), lattice(i + 1, j + 1, k + 1), u);
  return lerp(lerp(c00, c10, v), lerp(c01, c11, v), w);
}

}  // namespace skypol::sky::detail
