// The VRTE solver at one geometry, in the normalisation and sign convention of the Coulson, Dave &
// Sekera 1960 tables as corrected by Natraj, Li & Yung 2009 (ApJ 691, 1909): what `skypol table`
// prints, and how the solver is checked against them.
#pragma once

#include <span>
#include <vector>

#include "sky/vrte/atmosphere_optics.h"

namespace skypol::sky::vrte {

struct CoulsonIQU {
  double i = 0, q = 0, u = 0;
};

struct PointResult {
  CoulsonIQU top_up;       // reflected: leaving the top, seen looking down at nadir angle acos mu
  CoulsonIQU ground_down;  // transmitted (diffuse only): reaching the ground, seen looking up at zenith angle acos mu
};

// Normalisation: the sun's flux through a surface ⟂ its beam is π (Coulson's πF with F = 1), so
// I = π·(radiance / solar irradiance). The direct beam is not included.
// Geometry: mu0 = cos(sun zenith angle), mu = |cos| of the view's zenith/nadir angle, both in [0, 1];
// dphi_deg = the azimuth the observer looks towards minus the sun's azimuth (0: looking towards the
// sun's side, where the reflected light at the top has been scattered forwards).
// Signs: the tables' (Q, U) are skypol's Stokes (S1, S2) in the basis e0 = ẑ × d/|ẑ × d|
// (horizontal), e90 = d × e0, with d the direction the observer looks and Δφ counted
// counter-clockwise seen from above; equivalently Q_table = −S1 and U_table = −S2 in the meridian
// basis e0 = ∂d/∂θ, e90 = ẑ × d/|ẑ × d| (docs/conventions.md). Rayleigh light scattered at 90°
// has Q_table > 0 in the sun's vertical.
// streams: Gauss nodes per hemisphere. The default, 32, reproduces every value of Natraj et al.'s
// tables that tests/sky holds within 1e-6 (worst 9.3e-7, at τ = 0.02 and μ = 0.02; 1.2e-7 for
// μ ≥ 0.2); 16 within 3.1e-5 and 12 within 6.5e-5, worst at μ = 0.02 (the Gauss sums' error for a
// view so near the horizon), within 4e-6 for μ ≥ 0.2.
// Throws std::invalid_argument for inputs out of range.
PointResult coulson_point(double tau, double albedo, double depolarization, double mu0, double mu, double dphi_deg,
                          int streams = 32);

// The same for any layer (molecules and aerosol, LayerOptics).
PointResult coulson_point(const LayerOptics& optics, double albedo, double mu0, double mu, double dphi_deg,
                          int streams = 32);

// A whole table in one solve (what `skypol table` prints for a layer): every (mu0, mu, dphi)
// combination, same normalisation and signs as coulson_point. at(i0, i, k) indexes
// mu0[i0], mu[i], dphi_deg[k].
struct CoulsonTable {
  std::vector<double> mu0, mu, dphi_deg;
  std::vector<PointResult> values;
  const PointResult& at(std::size_t i0, std::size_t i, std::size_t k) const {
    return values[(i0 * mu.size() + i) * dphi_deg.size() + k];
  }
};
CoulsonTable coulson_table(const LayerOptics& optics, double albedo, std::span<const double> mu0,
                           std::span<const double> mu, std::span<const double> dphi_deg, int streams = 32);

}  // namespace skypol::sky::vrte
