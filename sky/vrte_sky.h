// The sky from the VRTE solver's table (vrte_table.h): multiple scattering by molecules and
// aerosol over a Lambertian ground, for one band. A colour scene builds one per band.
#pragma once

#include <memory>
#include <span>
#include <string>

#include "sky/sky_model.h"
#include "sky/vrte_table.h"

namespace skypol::sky {

// Radiance scale: S0 is the diffuse sky radiance per unit extraterrestrial solar irradiance
// (I/F, sr⁻¹; multiply by the band's solar irradiance in W m⁻² nm⁻¹ for W m⁻² sr⁻¹ nm⁻¹). This is
// not RayleighSky's relative unit (1 at 90° from the sun). The direct sun is not included
// (sun_disc.h adds a disc). Stokes vectors come in the basis (e0, d × e0) the caller gives, as for
// every SkyModel; S3 is not carried (0).
// Rules for the hard cases (all finite):
//  - sun on or below the horizon: 0 (a plane-parallel atmosphere lit at grazing incidence
//    receives no flux; twilight needs a spherical model);
//  - a view below the horizon: the Lambertian ground's radiance, unpolarized;
//  - a view or a sun at the zenith: the azimuth is taken from the other one (or North).
//  - where the table's interpolation would give a negative radiance (a sun within tenths of a
//    degree of the horizon) the sky is 0, and a degree above 1 is scaled back to 1.
class VrteSky final : public SkyModel {
 public:
  // Throws std::invalid_argument for a null or empty table.
  explicit VrteSky(std::shared_ptr<const vrte::VrteTable> table);
  std::string name() const override { return "vrte"; }
  Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const override;
  // The batch path interpolates the table to the sun once per call, then costs one interpolation
  // in μ and the Fourier sum per ray.
  void stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const override;
  void stokes_soa(const ViewRaysSoA& rays, const Sun& sun, const StokesSoA& out) const override;
  const vrte::VrteTable& table() const { return *table_; }

 private:
  std::shared_ptr<const vrte::VrteTable> table_;
};

}  // namespace skypol::sky
