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

}  // namespace skypol::sky
