// Seeded 3-D value noise (fractal sum of octaves), for procedural sky effects such as clouds.
// Deterministic: the same seed and point give the same value on every platform (integer hashing,
// float arithmetic in a fixed order, no library randomness).
#pragma once

#include <cstdint>

namespace skypol::sky::detail {

// Value noise at (x, y, z): lattice values hashed from (cell, seed), quintic-smoothed trilinear
// interpolation. Range [0, 1].
float value_noise(float x, float y, float z, std::uint64_t seed);

// `octaves` octaves of value_noise, each at twice the frequency and half the amplitude,
// normalised to [0, 1]; each octave uses its own seed so the octaves do not line up.
float fractal_noise(float x, float y, float z, std::uint64_t seed, int octaves);

}  // namespace skypol::sky::detail
