// Berry, Dennis & Lee 2004 ("Polarized light in the sky", New J. Phys. 6, 162): the real sky's
// neutral points. Rayleigh's two index-1 unpolarized points (sun, anti-sun) each split into two
// index-½ points on the solar vertical: Babinet above the sun, Brewster below it, Arago above the
// anti-sun (Brewster's antipode) and a fourth below it (Babinet's antipode). One parameter, the
// angular separation δ of each point from the sun (or anti-sun); δ = 0 is exactly Rayleigh.
#pragma once

#include <string_view>
#include <utility>

#include <Eigen/Core>

#include "sky/sky_model.h"

namespace skypol::sky {

// How BDL's intensity of polarization |w| becomes a degree (docs/conventions.md, "Berry sky").
// BDL (eq. 4.2) give w normalised to max |w| = 1, and |w| = sin γ1 sin γ2 = 4UV is their
// *intensity of polarization* (the "unnormalized degree"); they do not divide it by the sky's
// radiance. Two Rayleigh-consistent degrees are in use, equal at δ = 0 and in the AoLP:
//   split_rayleigh  |w|/(1 + cos γ1 cos γ2) = 2UV/(U² + V²)   (skypol's; the default)
//   opensky         |w|/(2 − |w|)           = 2UV/(1 − 2UV)   (OpenSky, Moutenet et al. 2024,
//                   IEEE TIM 73; PySkyLumos and py-sky-polarization)
// with U = sin(γ1/2) sin(γ2/2), V = cos(γ1/2) cos(γ2/2), γk the distances to the two neutral
// points near the sun. They differ by up to 0.126 in DoLP at δ = 15° (pair 30° apart).
enum class BerryNormalisation { split_rayleigh, opensky };

// "split_rayleigh" | "opensky"; throws std::invalid_argument listing the legal names.
BerryNormalisation parse_berry_normalisation(std::string_view name);
std::string_view berry_normalisation_name(BerryNormalisation n);

struct BerryParams {
  double max_dolp = 1.0;         // Pmax ∈ [0, 1]
  double separation_deg = 0.0;  // δ ∈ [0°, 45°]: each neutral point's distance from the sun
  BerryNormalisation normalisation = BerryNormalisation::split_rayleigh;
};

// BDL's pattern in vector form (derivation in berry.cpp). With p1 (Babinet) and p2 (Brewster) the
// sun turned by ±δ along the solar vertical, ck = d·pk and τk = pk·e0 + i pk·e90 (the tangent
// towards pk, |τk| = sin∠(d, pk)), BDL's field is w ∝ −τ1 τ2 and |w| = |τ1||τ2|:
//   S1 + i S2 = −S0 · Pmax · τ1 τ2 / N,   S0 = 1 + (d·s)²  (Rayleigh phase),
//   DoLP = Pmax |w| / N,  N = 1 + c1 c2 (split_rayleigh) or 2 − |τ1||τ2| (opensky).
// For δ = 0, τ1 = τ2 and both are Rayleigh's −Pmax τ² exactly.
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
