// Berry, Dennis & Lee 2004 ("Polarized light in the sky", New J. Phys. 6, 162): the real sky's
// neutral points. Rayleigh's two index-1 unpolarized points (sun, anti-sun) each split into two
// index-½ points on the solar vertical: Babinet above the sun, Brewster below it, Arago above the
// anti-sun (Brewster's antipode) and a fourth below it (Babinet's antipode). One parameter, the
// angular separation δ of each point from the sun (or anti-sun); δ = 0 is exactly Rayleigh.
#pragma once

#include <utility>

#include <Eigen/Core>

#include "sky/sky_model.h"

namespace skypol::sky {

struct BerryParams {
  double max_dolp = 1.0;         // Pmax ∈ [0, 1]
  double separation_deg = 0.0;  // δ ∈ [0°, 45°]: each neutral point's distance from the sun
};

// BDL's pattern in vector form (derivation in berry.cpp). With p1 (Babinet) and p2 (Brewster) the
// sun turned by ±δ along the solar vertical, ck = d·pk and τk = pk·e0 + i pk·e90 (the tangent
// towards pk, |τk| = sin∠(d, pk)):
//   S1 + i S2 = −S0 · Pmax · τ1 τ2 / (1 + c1 c2),   S0 = 1 + (d·s)²  (Rayleigh phase),
//   DoLP = Pmax |τ1||τ2| / (1 + c1 c2) = Pmax · 2UV/(U² + V²),  U = sin(γ1/2) sin(γ2/2),
//   V = cos(γ1/2) cos(γ2/2) — BDL's |w| normalisation written on the sphere.
// For δ = 0, τ1 = τ2 and this is Rayleigh's −Pmax τ² exactly.
class BerrySky final : public SkyModel {
 public:
  explicit BerrySky(BerryParams params = {});  // throws std::invalid_argument out of range
  std::string name() const override { return "berry"; }
  Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const override;
  void stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const override;
  const BerryParams& params() const { return params_; }

  // The Babinet (first) and Brewster (second) neutral points for a sun, as ENU unit vectors; the
  // Arago point and the fourth are their antipodes (−second, −first). For a sun at the zenith or
  // nadir the solar vertical is taken at sun.azimuth (documented rule).
  std::pair<Eigen::Vector3d, Eigen::Vector3d> neutral_points(const Sun& sun) const;

 private:
  BerryParams params_;
};

}  // namespace skypol::sky
