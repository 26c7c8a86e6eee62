// The optical properties of a plane-parallel atmosphere at one wavelength: what the aerosol and
// spectral code (mie.h, optical_depth.h) produces and what the vector radiative transfer solver
// consumes. Plain values only, so either side can be built and tested alone.
#pragma once

#include <vector>

namespace skypol::sky {

// The scattering matrix of a macroscopically isotropic, mirror-symmetric medium (randomly oriented
// spheres, molecules), as a function of the scattering angle Θ (van de Hulst 1957; Hovenier et al.
// 2004, eq. 2.172): six independent elements
//   | F11 F12  0   0  |
//   | F12 F22  0   0  |
//   |  0   0  F33 F34 |
//   |  0   0 −F34 F44 |
// with Stokes Q referred to the scattering plane (Q > 0: E parallel to it). In this convention a
// Rayleigh scatterer has F12 = −¾ sin²Θ (light scattered at 90° is polarized perpendicular to the
// scattering plane), and Bohren & Huffman's amplitude functions give F11 = ½(|S2|²+|S1|²),
// F12 = ½(|S2|²−|S1|²), F33 = Re(S2 S1*), F34 = Im(S2 S1*), each scaled by one common factor.
// Normalisation: ½ ∫₋₁¹ F11(μ) dμ = 1 (the phase function averages to 1 over the sphere).
struct ScatteringMatrixTable {
  std::vector<double> cos_theta;  // nodes, strictly ascending in [−1, 1] (e.g. Gauss–Legendre)
  std::vector<double> weight;     // quadrature weights on those nodes, Σ = 2 (empty: none)
  std::vector<double> f11, f12, f22, f33, f34, f44;  // one value per node
};

// One homogeneous layer at one wavelength: molecules plus, optionally, one aerosol component.
struct LayerOptics {
  double wavelength_nm = 550.0;
  double tau_rayleigh = 0.0;          // molecular scattering optical depth (vertical)
  double depolarization = 0.0;        // molecular depolarization factor ρ_n (King correction)
  double tau_aerosol = 0.0;           // aerosol extinction optical depth (vertical)
  double aerosol_ssa = 1.0;           // aerosol single-scattering albedo ω ∈ [0, 1]
  ScatteringMatrixTable aerosol;      // needed when tau_aerosol > 0
};

}  // namespace skypol::sky
