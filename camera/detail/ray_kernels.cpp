// The row loops of ray_kernels.h. Each is one loop over arrays with selects instead of branches, so
// GCC runs it as vector code (-fno-math-errno, -fno-trapping-math: camera/CMakeLists.txt). Column
// indices convert to double through int (a row is < 2³¹ pixels): AVX2 converts 32-bit integers to
// double, not 64-bit ones, and an unsigned conversion would keep the loop scalar.
#include "camera/detail/ray_kernels.h"

namespace skypol::camera::detail {

// Compiled for the baseline and for AVX2, picked at load time (as sky/vector_clones.h does for the
// sky's loops, which camera/ may not include). No FMA in either clone, so both round alike.
#if defined(__x86_64__) && defined(__linux__) && defined(__GNUC__) && !defined(__clang__)
#define SKYPOL_RAY_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SKYPOL_RAY_CLONES
#endif

SKYPOL_RAY_CLONES void row_radii(double x0, std::size_t i0, double cx, double fx, double my, std::size_t n,
                                 double* __restrict mx, double* __restrict r) {
  for (std::size_t i = 0; i < n; ++i) {
    mx[i] = (x0 + static_cast<double>(static_cast<int>(i0 + i)) - cx) / fx;
    r[i] = std::sqrt(mx[i] * mx[i] + my * my);
  }
}

SKYPOL_RAY_CLONES void radial_directions(std::size_t n, std::size_t lo, std::size_t hi, double my, double limit,
                                         const double* __restrict mx, const double* __restrict r,
                                         const double* __restrict theta, double* __restrict dx,
                                         double* __restrict dy, double* __restrict dz,
                                         unsigned char* __restrict valid) {
  for (std::size_t i = 0; i < n; ++i) valid[i] = i >= lo && i < hi && r[i] <= limit ? 1 : 0;
  for (std::size_t i = 0; i < lo; ++i) dx[i] = 0, dy[i] = 0, dz[i] = 1;
  for (std::size_t i = hi; i < n; ++i) dx[i] = 0, dy[i] = 0, dz[i] = 1;
  for (std::size_t i = lo; i < hi; ++i) {
    double s, c;
    sin_cos(theta[i], s, c);
    const double k = s / r[i];
    const bool off_axis = r[i] <= limit && r[i] > 0;  // else d = +z (direction()'s axis case)
    dx[i] = off_axis ? k * mx[i] : 0.0;
    dy[i] = off_axis ? k * my : 0.0;
    dz[i] = off_axis ? c : 1.0;
  }
}

SKYPOL_RAY_CLONES void world_rays(const Rotation rot, std::size_t n, std::size_t lo, std::size_t hi,
                                  const double* __restrict cx, const double* __restrict cy,
                                  const double* __restrict cz, const unsigned char* __restrict valid,
                                  float* __restrict odx, float* __restrict ody, float* __restrict odz,
                                  float* __restrict oux, float* __restrict ouy, float* __restrict ouz,
                                  float* __restrict ovalid) {
  // The weights first, in a loop of their own: bytes and doubles in one loop keep GCC from
  // vectorizing it.
  for (std::size_t i = 0; i < n; ++i) ovalid[i] = valid[i] ? 1.0f : 0.0f;
  auto outside = [&](std::size_t i) { odx[i] = 0, ody[i] = 0, odz[i] = 1, oux[i] = 1, ouy[i] = 0, ouz[i] = 0; };
  for (std::size_t i = 0; i < lo; ++i) outside(i);
  for (std::size_t i = hi; i < n; ++i) outside(i);
  for (std::size_t i = lo; i < hi; ++i) {
    const bool ok = ovalid[i] != 0;
    double wx, wy, wz, ex, ey, ez, ux, uy, uz;
    rotate(rot, cx[i], cy[i], cz[i], wx, wy, wz);
    meridional_e0(cx[i], cy[i], cz[i], ex, ey, ez);
    rotate(rot, ex, ey, ez, ux, uy, uz);
    odx[i] = ok ? static_cast<float>(wx) : 0.0f;
    ody[i] = ok ? static_cast<float>(wy) : 0.0f;
    odz[i] = ok ? static_cast<float>(wz) : 1.0f;
    oux[i] = ok ? static_cast<float>(ux) : 1.0f;
    ouy[i] = ok ? static_cast<float>(uy) : 0.0f;
    ouz[i] = ok ? static_cast<float>(uz) : 0.0f;
  }
}

}  // namespace skypol::camera::detail
