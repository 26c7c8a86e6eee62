// Value noise: one pseudo-random number per integer lattice point (splitmix64 finalizer of the
// cell and the seed), blended with the quintic fade 6t⁵ − 15t⁴ + 10t³ (C² continuous, so no
// visible creases at cell borders).
#include "sky/noise.h"

#include <cmath>

namespace skypol::sky::detail {
namespace {

std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

float lattice(std::int64_t i, std::int64_t j, std::int64_t k, std::uint64_t seed) {
  std::uint64_t h = mix(seed);
  h = mix(h ^ static_cast<std::uint64_t>(i));
  h = mix(h ^ static_cast<std::uint64_t>(j));
  h = mix(h ^ static_cast<std::uint64_t>(k));
  return static_cast<float>(h >> 40) * (1.0f / 16777216.0f);  // top 24 bits → [0, 1)
}

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
float lerp(float a, float b, float t) { return a + (b - a) * t; }

}  // namespace

float value_noise(float x, float y, float z, std::uint64_t seed) {
  const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const auto i = static_cast<std::int64_t>(fx), j = static_cast<std::int64_t>(fy), k = static_cast<std::int64_t>(fz);
  const float u = fade(x - fx), v = fade(y - fy), w = fade(z - fz);
  const float c00 = lerp(lattice(i, j, k, seed), lattice(i + 1, j, k, seed), u);
  const float c10 = lerp(lattice(i, j + 1, k, seed), lattice(i + 1, j + 1, k, seed), u);
  const float c01 = lerp(lattice(i, j, k + 1, seed), lattice(i + 1, j, k + 1, seed), u);
  const float c11 = lerp(lattice(i, j + 1, k + 1, seed), lattice(i + 1, j + 1, k + 1, seed), u);
  return lerp(lerp(c00, c10, v), lerp(c01, c11, v), w);
}

float fractal_noise(float x, float y, float z, std::uint64_t seed, int octaves) {
  float sum = 0.0f, amplitude = 1.0f, total = 0.0f, frequency = 1.0f;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * value_noise(x * frequency, y * frequency, z * frequency, seed + static_cast<std::uint64_t>(o) * 0x632be59bd9b4e019ULL);
    total += amplitude;
    amplitude *= 0.5f;
    frequency *= 2.0f;
  }
  return sum / total;
}

}  // namespace skypol::sky::detail
