// The polarized sky: radiance and linear polarization of the clear sky in any direction, for a sun.
// Models are evaluated in vector form (E ∝ d × s, cos γ = d·s): no closed form with tan α, so the
// zenith and a sun at the zenith are ordinary points.
#pragma once

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
};

}  // namespace skypol::sky
