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

// Plain float arithmetic on named scalars read from structure-of-arrays blocks, no calls and no
// branches in the body, so that GCC vectorizes the inner loop (checked with -fopt-info-vec).
void RayleighSky::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  if (out.size() < rays.size()) rays = rays.first(out.size());
  const float sx = static_cast<float>(sun.direction.x());
  const float sy = static_cast<float>(sun.direction.y());
  const float sz = static_cast<float>(sun.direction.z());
  const float pm = static_cast<float>(params_.max_dolp);
  detail::for_each_ray_block(rays, [&](const detail::RayBlock& b) {
    StokesF* __restrict o = out.data() + b.first;
    for (std::size_t j = 0; j < b.count; ++j) {
      const float dx = b.dx[j], dy = b.dy[j], dz = b.dz[j];
      const float ux = b.ux[j], uy = b.uy[j], uz = b.uz[j];
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
      const float b90 = ex * vx + ey * vy + ez * vz;
      o[j].s0 = 1.0f + c * c;
      o[j].s1 = pm * (a * a - b90 * b90);
      o[j].s2 = pm * 2.0f * a * b90;
      o[j].s3 = 0.0f;
    }
  });
}

}  // namespace skypol::sky
