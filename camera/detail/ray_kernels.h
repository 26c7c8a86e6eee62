// The per-pixel arithmetic of the batched ray paths (Lens::ray_row of the radial models,
// Camera::ray_row) as plain loops over arrays that the compiler runs as vector code, and the one
// sin/cos they and ray() share. Pure IEEE arithmetic without FMA: the scalar and the vector code,
// and the baseline and AVX2 builds, round every operation alike, so ray_row keeps ray()'s bits.
// Not part of the camera interface.
#pragma once

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace skypol::camera::detail {

// sin x and cos x, within ~1 ulp for |x| < 1e5 (ray angles are in [0, π]). A polynomial rather than
// the library's: it inlines into the row loops and vectorizes (a libm call does neither), and it
// gives the same bits in ray() and ray_row on every machine. x = k·π/2 + t, |t| ≤ π/4 (Cody–Waite:
// π/2 as a 33-bit head, so k·head is exact, plus a tail); then the Taylor series of sin t and cos t
// to t¹⁷ and t¹⁶, whose next terms are < 1e-19 and < 3e-18 for |t| ≤ π/4.
inline void sin_cos(double x, double& s, double& c) {
  constexpr double kTwoOverPi = 0.63661977236758134308;
  constexpr double kShift = 0x1.8p52;  // adding it rounds to an integer, held in the low mantissa bits
  constexpr double kPio2Head = 1.57079632673412561417e+00;  // fdlibm's pio2_1: 33 bits of π/2
  constexpr double kPio2Tail = 6.07710050650619224932e-11;  // π/2 − pio2_1
  const double kd = x * kTwoOverPi + kShift;
  const double k = kd - kShift;
  const std::uint64_t q = std::bit_cast<std::uint64_t>(kd);  // k mod 4 in the low two bits
  const double t = (x - k * kPio2Head) - k * kPio2Tail;
  const double z = t * t;
  constexpr double s3 = -1.0 / 6, s5 = 1.0 / 120, s7 = -1.0 / 5040, s9 = 1.0 / 362880, s11 = -1.0 / 39916800,
                   s13 = 1.0 / 6227020800, s15 = -1.0 / 1307674368000, s17 = 1.0 / 355687428096000;
  constexpr double c2 = -1.0 / 2, c4 = 1.0 / 24, c6 = -1.0 / 720, c8 = 1.0 / 40320, c10 = -1.0 / 3628800,
                   c12 = 1.0 / 479001600, c14 = -1.0 / 87178291200, c16 = 1.0 / 20922789888000;
  const double st = t + t * z * (s3 + z * (s5 + z * (s7 + z * (s9 + z * (s11 + z * (s13 + z * (s15 + z * s17)))))));
  const double ct = 1 + z * (c2 + z * (c4 + z * (c6 + z * (c8 + z * (c10 + z * (c12 + z * (c14 + z * c16)))))));
  // Quadrant k mod 4: sin x = st, ct, −st, −ct and cos x = ct, −st, −ct, st. Bit operations, so
  // the selects vectorize.
  const std::uint64_t bs = std::bit_cast<std::uint64_t>(st), bc = std::bit_cast<std::uint64_t>(ct);
  const std::uint64_t swap = std::uint64_t{0} - (q & 1);  // all ones in odd quadrants
  const std::uint64_t sin_bits = bs ^ ((bs ^ bc) & swap), cos_bits = bc ^ ((bs ^ bc) & swap);
  s = std::bit_cast<double>(sin_bits ^ ((q & 2) << 62));
  c = std::bit_cast<double>(cos_bits ^ (((q + 1) & 2) << 62));
}

// meridional_e0 (camera.h) of the camera direction (x, y, z), without branches so that it
// vectorizes: d = (x, y, z)/|(x, y, z)|, e0 = (1 − dx·q, −dy·q, −dx) with q = dx/(1 + dz), or
// q = dx·(1 − dz)/(dx² + dy²) when dz < 0 (1 + dz loses its digits near the backward axis); +x for
// a zero or non-finite direction and −x straight back. e0 is unit for a unit d (|e0|² = 1 exactly
// in real arithmetic), so it is not normalized again: one square root and two divisions a pixel.
inline void meridional_e0(double x, double y, double z, double& ex, double& ey, double& ez) {
  const double n = std::sqrt((x * x + y * y) + z * z);
  const bool usable = n > 0 && n <= std::numeric_limits<double>::max();
  const double inv_n = 1 / n;  // reciprocals: a division costs several multiplications
  const double dx = x * inv_n, dy = y * inv_n, dz = z * inv_n;
  const double rho2 = dx * dx + dy * dy;
  const bool front = dz >= 0;
  const double den = front ? 1 + dz : rho2;
  // θ = π, φ = 0 limit: den ≥ 1 in front, so only dz < 0 can be back (one comparison: combining
  // bools keeps GCC from vectorizing).
  const bool back = !(den > 1e-300 * (1 - dz));
  const double q = (front ? dx : dx * (1 - dz)) / den;
  ex = !usable ? 1.0 : back ? -1.0 : 1 - dx * q;
  ey = !usable || back ? 0.0 : -dy * q;
  ez = !usable || back ? 0.0 : -dx;
}

// A 3×3 rotation by rows, as scalars: the row loops keep them in registers (an array is
// reloaded, and then GCC does not vectorize).
struct Rotation {
  double xx, xy, xz, yx, yy, yz, zx, zy, zz;
};

// R·v.
inline void rotate(const Rotation& r, double x, double y, double z, double& ox, double& oy, double& oz) {
  ox = (r.xx * x + r.xy * y) + r.xz * z;
  oy = (r.yx * x + r.yy * y) + r.yz * z;
  oz = (r.zx * x + r.zy * y) + r.zz * z;
}

// The normalized coordinates mx[i] = (x0 + (i0 + i) − cx)/fx and radii r[i] = √(mx² + my²) of the
// n pixels (x0 + i0 + i, y) of a row, my given: normalized_within's arithmetic.
void row_radii(double x0, std::size_t i0, double cx, double fx, double my, std::size_t n, double* mx, double* r);

// The unit directions of those pixels from their radii and field angles theta[i]
// (radial_ray_row): valid[i] = r[i] ≤ limit, d = (sin θ·mx/r, sin θ·my/r, cos θ), d = (0, 0, 1) on
// the axis and where not valid. direction()'s arithmetic. Only [lo, hi) may be valid (the span of
// the row inside the image circle); theta is read there only.
void radial_directions(std::size_t n, std::size_t lo, std::size_t hi, double my, double limit, const double* mx,
                       const double* r, const double* theta, double* dx, double* dy, double* dz,
                       unsigned char* valid);

// Camera::ray_row's second half: for camera-frame directions c[i] (valid[i]), the world direction
// R·c and the world polarizer direction R·meridional_e0(c), cast to float (camera.h); where not
// valid, d = +z, e0 = +x, weight 0. Only [lo, hi) may be valid. The same arithmetic as
// Camera::ray(). The outputs are separate restrict parameters: GCC trusts those, and would
// otherwise need more run-time alias checks than it makes before vectorizing.
void world_rays(Rotation rot, std::size_t n, std::size_t lo, std::size_t hi, const double* cx, const double* cy,
                const double* cz, const unsigned char* valid, float* dx, float* dy, float* dz, float* ux, float* uy,
                float* uz, float* weight);

// [lo, hi): from the first to past the last i < n with ok(i), or lo = hi = n if none.
template <class Ok>
void valid_span(std::size_t n, Ok ok, std::size_t& lo, std::size_t& hi) {
  lo = 0;
  while (lo < n && !ok(lo)) ++lo;
  hi = n;
  while (hi > lo && !ok(hi - 1)) --hi;
  if (lo == hi) lo = hi = n;
}

}  // namespace skypol::camera::detail
