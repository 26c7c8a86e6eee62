// The polarized sky: radiance and linear polarization of the clear sky in any direction, for a sun.
// Models are evaluated in vector form (E ∝ d × s, cos γ = d·s): no closed form with tan α, so the
// zenith and a sun at the zenith are ordinary points.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>

#include <Eigen/Core>
// Users of ViewRay build bases with cross(), which Eigen declares in Core but defines in Geometry:
// without this include a missing definition shows up only at link time.
#include <Eigen/Geometry>

#include "sky/stokes.h"
#include "sky/sun.h"

namespace skypol::sky {

// One viewing direction with the basis its Stokes vector is wanted in (docs/conventions.md):
// d is the unit direction the observer looks along (ENU), e0 a unit vector ⟂ d; e90 = d × e0.
struct ViewRay {
  Eigen::Vector3f d;
  Eigen::Vector3f e0;
};

// Stokes result in float, as the renderer stores it.
struct StokesF {
  float s0, s1, s2, s3;
};

// Many rays in structure-of-arrays form: ray i has d = (dx[i], dy[i], dz[i]) and
// e0 = (ux[i], uy[i], uz[i]). The renderer caches its camera rays this way: a model's float loop
// then reads six contiguous arrays, which the compiler vectorizes without a gather or a copy.
struct ViewRaysSoA {
  std::size_t count = 0;
  const float* dx = nullptr;
  const float* dy = nullptr;
  const float* dz = nullptr;
  const float* ux = nullptr;
  const float* uy = nullptr;
  const float* uz = nullptr;
};

// Where a structure-of-arrays evaluation writes: count floats at each pointer (distinct arrays).
struct StokesSoA {
  float* s0 = nullptr;
  float* s1 = nullptr;
  float* s2 = nullptr;
  float* s3 = nullptr;
};

// Models are immutable once built: every const member function may be called from many threads
// at once (the renderer's tiles share one model).
class SkyModel {
 public:
  virtual ~SkyModel() = default;
  virtual std::string name() const = 0;

  // Stokes of the light arriving from direction ray.d, in the basis (ray.e0, ray.d × ray.e0).
  virtual Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const = 0;

  // Many directions at once (the renderer's path). The default loops over stokes(); models
  // override it with a float loop the compiler vectorizes. out.size() == rays.size().
  virtual void stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const;

  // The same in structure-of-arrays form (the renderer's path at one sample per pixel). The default
  // goes through the ViewRay path in small blocks; models the renderer uses most override it.
  virtual void stokes_soa(const ViewRaysSoA& rays, const Sun& sun, const StokesSoA& out) const;
};

}  // namespace skypol::sky
