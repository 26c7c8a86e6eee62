// The generic many-directions path: correct for every model, fast for none. Models that the
// renderer uses per pixel override it with a float loop (see rayleigh.cpp).
#include "sky/sky_model.h"

#include <cassert>
#include <cstddef>

namespace skypol::sky {

void SkyModel::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  const std::size_t n = rays.size() < out.size() ? rays.size() : out.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Stokes s = stokes(rays[i].d.cast<double>(), rays[i].e0.cast<double>(), sun);
    out[i] = {static_cast<float>(s.s0), static_cast<float>(s.s1), static_cast<float>(s.s2),
              static_cast<float>(s.s3)};
  }
}

void SkyModel::stokes_soa(const ViewRaysSoA& rays, const Sun& sun, const StokesSoA& out) const {
  constexpr std::size_t kBlock = 128;
  ViewRay in[kBlock];
  StokesF res[kBlock];
  for (std::size_t first = 0; first < rays.count; first += kBlock) {
    const std::size_t n = rays.count - first < kBlock ? rays.count - first : kBlock;
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t i = first + j;
      in[j].d = Eigen::Vector3f(rays.dx[i], rays.dy[i], rays.dz[i]);
      in[j].e0 = Eigen::Vector3f(rays.ux[i], rays.uy[i], rays.uz[i]);
    }
    stokes(std::span<const ViewRay>(in, n), sun, std::span<StokesF>(res, n));
    for (std::size_t j = 0; j < n; ++j) {
      out.s0[first + j] = res[j].s0;
      out.s1[first + j] = res[j].s1;
      out.s2[first + j] = res[j].s2;
      out.s3[first + j] = res[j].s3;
    }
  }
}

}  // namespace skypol::sky
