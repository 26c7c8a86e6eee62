// Rayleigh sky in vector form. With d the viewing direction, s the sun, (e0, e90 = d × e0) the
// basis, cos γ = d·s and E = d × s (|E| = sin γ, E ⟂ d and ⟂ s: the E-vector of light singly
// scattered by a dipole is normal to the scattering plane):
//   S0 = 1 + cos²γ,  S1 = Pmax·(a² − b²),  S2 = Pmax·2ab,  S3 = 0,  a = E·e0, b = E·e90.
// Then DoLP = Pmax·(a²+b²)/(1+cos²γ) = Pmax·sin²γ/(1+cos²γ) and AoLP = atan2(b, a): no trig, no
// division, nothing singular at the zenith, at the sun or at the anti-sun (E = 0 gives S1 = S2 = 0
// exactly). S0 = 1 at γ = 90°.
#include "sky/rayleigh.h"

#include <cassert>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "sky/ray_block.h"
#include "sky/vector_clones.h"

namespace skypol::sky {

RayleighSky::RayleighSky(RayleighParams params) : params_(params) {
  if (!(params_.max_dolp >= 0.0 && params_.max_dolp <= 1.0)) {
    throw std::invalid_argument("rayleigh: max_dolp (Pmax) " + std::to_string(params_.max_dolp) +
                                " must be in [0, 1]");
  }
}

Stokes RayleighSky::stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const {
  const Eigen::Vector3d& s = sun.direction;
  const double c = d.dot(s);
  const Eigen::Vector3d e = d.cross(s);
  const Eigen::Vector3d e90 = d.cross(e0);
  const double a = e.dot(e0);
  const double b = e.dot(e90);
  const double p = params_.max_dolp;
  return {1.0 + c * c, p * (a * a - b * b), p * 2.0 * a * b, 0.0};
}

namespace {

// The sun and Pmax in float, as the per-pixel loop uses them.
struct FloatParams {
  float sx, sy, sz, pm;
};

FloatParams float_params(const Sun& sun, double max_dolp) {
  return {static_cast<float>(sun.direction.x()), static_cast<float>(sun.direction.y()),
          static_cast<float>(sun.direction.z()), static_cast<float>(max_dolp)};
}

// The model in float on arrays: plain arithmetic on named scalars, no calls and no branches in the
// body, restrict-qualified arrays, so that GCC vectorizes the loop (checked with -fopt-info-vec).
// The ViewRay path and the structure-of-arrays path both end here, so they agree bit for bit.
SKYPOL_VECTOR_CLONES void rayleigh_float(const FloatParams& p, std::size_t n, const float* __restrict dx_,
                                         const float* __restrict dy_, const float* __restrict dz_,
                                         const float* __restrict ux_, const float* __restrict uy_,
                                         const float* __restrict uz_, float* __restrict s0, float* __restrict s1,
                                         float* __restrict s2, float* __restrict s3) {
  const float sx = p.sx, sy = p.sy, sz = p.sz, pm = p.pm;
  for (std::size_t j = 0; j < n; ++j) {
    const float dx = dx_[j], dy = dy_[j], dz = dz_[j];
    const float ux = ux_[j], uy = uy_[j], uz = uz_[j];
    const float c = dx * sx + dy * sy + dz * sz;
    // E = d × s
    const float ex = dy * sz - dz * sy;
    const float ey = dz * sx - dx * sz;
    const float ez = dx * sy - dy * sx;
    // e90 = d × e0
    const float vx = dy * uz - dz * uy;
    const float vy = dz * ux - dx * uz;
    const float vz = dx * uy - dy * ux;
    const float a = ex * ux + ey * uy + ez * uz;
    const float b = ex * vx + ey * vy + ez * vz;
    s0[j] = 1.0f + c * c;
    s1[j] = pm * (a * a - b * b);
    s2[j] = pm * 2.0f * a * b;
    s3[j] = 0.0f;
  }
}

}  // namespace

void RayleighSky::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  if (out.size() < rays.size()) rays = rays.first(out.size());
  const FloatParams p = float_params(sun, params_.max_dolp);
  detail::for_each_ray_block(rays, [&](const detail::RayBlock& b) {
    alignas(32) float s0[detail::RayBlock::kSize], s1[detail::RayBlock::kSize], s2[detail::RayBlock::kSize],
        s3[detail::RayBlock::kSize];
    rayleigh_float(p, b.count, b.dx, b.dy, b.dz, b.ux, b.uy, b.uz, s0, s1, s2, s3);
    StokesF* o = out.data() + b.first;
    for (std::size_t j = 0; j < b.count; ++j) o[j] = {s0[j], s1[j], s2[j], s3[j]};
  });
}

void RayleighSky::stokes_soa(const ViewRaysSoA& rays, const Sun& sun, const StokesSoA& out) const {
  rayleigh_float(float_params(sun, params_.max_dolp), rays.count, rays.dx, rays.dy, rays.dz, rays.ux, rays.uy, rays.uz,
                 out.s0, out.s1, out.s2, out.s3);
}

}  // namespace skypol::sky
