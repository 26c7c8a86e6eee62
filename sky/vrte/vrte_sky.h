// The sky from the VRTE solver's table (vrte_table.h): multiple scattering by molecules and
// aerosol over a Lambertian ground, for one band. A colour scene builds one per band.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "sky/sky_model.h"
#include "sky/vrte/vrte_table.h"

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
//
// Two paths give the same sky. stokes(d, e0, sun) evaluates the table in double: the slice to the
// sun, one interpolation in μ, the Fourier sum and the exact single scattering. The batch paths
// (the renderer's) prepare once per sun what does not depend on the pixel (SunPlan: the multiple
// scattering summed over azimuth at each of the table's μ nodes on a fine azimuth grid, the
// single-scattering factor on a fine μ grid) and then cost a float loop with no Fourier sum: the
// same cubic interpolation in μ, a linear one in azimuth and in the scattering angle
// (sky/README.md gives how far the two paths differ: well below the table's own error). A plan
// costs about 25 × 3 × 1026 × terms multiply-adds and 0.3 MB; the last four suns' are kept.
class VrteSky final : public SkyModel {
 public:
  // Throws std::invalid_argument for a null or empty table.
  explicit VrteSky(std::shared_ptr<const vrte::VrteTable> table);
  std::string name() const override { return "vrte"; }
  Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const override;
  void stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const override;
  void stokes_soa(const ViewRaysSoA& rays, const Sun& sun, const StokesSoA& out) const override;
  const vrte::VrteTable& table() const { return *table_; }

  // A colour scene's bands at once: skies[i] into out[i], each bit for bit what its own stokes_soa
  // writes, with what does not depend on the band (the view's stencils in μ and azimuth, the
  // scattering angle and the nodes below it, the turn into the caller's basis) computed once for
  // them all. Returns false, having written nothing, unless there are 2 to kMaxBands models, all
  // of them VrteSky on tables of one grid, and as many outputs.
  static constexpr std::size_t kMaxBands = 8;
  static bool stokes_soa_bands(std::span<const SkyModel* const> skies, const ViewRaysSoA& rays, const Sun& sun,
                               std::span<const StokesSoA> out);

  // The fine grids of the batch paths: azimuth nodes per half of [0, π] (tan(Δφ/2) and
  // cot(Δφ/2) uniform in [0, 1]) and μ nodes of the single-scattering factor (uniform in the
  // table's v).
  static constexpr int kAzimuthSteps = 512;
  static constexpr int kFactorSteps = 2048;

 private:
  struct SunPlan;
  std::shared_ptr<const SunPlan> plan(const Sun& sun) const;

  std::shared_ptr<const vrte::VrteTable> table_;
  std::vector<float> phase_;           // per scattering-angle node k (Θ = kπ/(n − 1)): ωF11, −ωF12/sin²Θ
  std::vector<double> cos_m_, sin_m_;  // [m·J + j]: cos mΔφ_j, sin mΔφ_j at the azimuth nodes
  // The plans of the last few suns: a frame's chunks share one; callers that render several
  // suns at once each find theirs.
  mutable std::mutex mutex_;
  mutable std::array<std::shared_ptr<const SunPlan>, 4> plans_;
  mutable std::size_t next_plan_ = 0;
};

}  // namespace skypol::sky
