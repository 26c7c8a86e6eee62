// The scattering matrix the VRTE solver sees: molecules (Rayleigh with depolarization) plus an
// aerosol given as a table, expanded in generalized spherical functions and delta-M truncated so
// that a few streams integrate it (Wiscombe 1977; the vector expansion of Hovenier et al. 2004, ch. 2).
#pragma once

#include <array>
#include <vector>

#include "sky/vrte/atmosphere_optics.h"

namespace skypol::sky::vrte {

// The six elements of a scattering matrix at one angle (atmosphere_optics.h's convention:
// Q referred to the scattering plane, Rayleigh F12 = −¾ sin²Θ).
struct Elements {
  double f11 = 0, f12 = 0, f22 = 0, f33 = 0, f34 = 0, f44 = 0;
};

// Hansen & Travis 1974 (Space Sci. Rev. 16, 527), §2: Rayleigh with depolarization factor ρ,
// Δ = (1 − ρ)/(1 + ρ/2), Δ' = (1 − 2ρ)/(1 − ρ); ½∫F11 dμ = 1.
Elements rayleigh_elements(double cos_theta, double depolarization);

// Wigner d-functions d^l_{mn}(Θ) for l = 0..lmax at x = cos Θ, for the four (m, n) the expansion
// uses: (0,0) = Legendre P_l, (0,2), (2,2), (2,−2). Three-term recurrence in l (Mishchenko, Travis & Lacis 2002,
// appendix B).
struct WignerRows {
  std::vector<double> d00, d02, d22, d2m2;
};
WignerRows wigner_rows(double cos_theta, int lmax);

// Expansion of a scattering matrix (Hovenier et al. 2004, ch. 2, written with real d-functions):
//   F11 = Σ a1_l d00,  F44 = Σ a4_l d00,  F22+F33 = Σ p_l d22,  F22−F33 = Σ q_l d2m2,
//   F12 = Σ b1_l d02,  F34 = Σ b2_l d02.
// Coefficients are projections: c_l = (2l+1)/2 ∫ f d^l dx (the d^l are orthogonal with norm 2/(2l+1)).
struct GreekCoefficients {
  std::vector<double> a1, a4, p, q, b1, b2;  // index l = 0..lmax
  int lmax() const { return static_cast<int>(a1.size()) - 1; }
  Elements evaluate(double cos_theta) const;
};

// Projects a table onto l = 0..lmax with the table's own quadrature weights; a table without
// weights is read as piecewise linear in cos Θ and integrated on fine Gauss nodes. With n nodes
// and weights, orders above n − 1 (which the quadrature cannot resolve) are set to 0: give a Mie
// table at least 2N + 1 nodes for 2N streams. Throws std::invalid_argument for a malformed table (sizes, order, range).
GreekCoefficients expand(const ScatteringMatrixTable& table, int lmax);

// Delta-M: F = (1 − f)·F' + f·2δ(1 − cos Θ)·1, with f = a1_{L+1}/(2L+3) so that F' keeps only
// l ≤ L. The forward peak goes into the direct beam (τ' = (1 − ωf)τ, Wiscombe 1977).
struct Truncated {
  GreekCoefficients coefficients;  // F', l ≤ L
  double f = 0;                    // the peak's fraction of the scattered light
};
Truncated delta_m(const GreekCoefficients& full, int L);

// The full untruncated aerosol matrix at any angle: linear in Θ on a fine uniform grid, for the
// exact single-scattering term the sky adds per ray.
class AngleTable {
 public:
  AngleTable() = default;
  explicit AngleTable(const ScatteringMatrixTable& table, int samples = 3601);
  Elements at(double cos_theta) const;
  bool empty() const { return rows_.empty(); }

 private:
  std::vector<Elements> rows_;  // at Θ_k = kπ/(n − 1)
};

// One homogeneous layer as the solver sees it after truncation: τ' (extinction), and ω'F'(Θ)
// split into its molecular and aerosol parts. rayleigh_weight = τ_R/τ',
// aerosol_weight = ω_A τ_A (1 − f)/τ'; ω' = their sum.
struct ScaledLayer {
  double tau = 0;
  double rayleigh_weight = 0;
  double aerosol_weight = 0;
  double depolarization = 0;
  bool has_aerosol = false;
  GreekCoefficients aerosol;  // truncated
  int lmax = 2;               // highest l of ω'F' (2 for molecules alone)

  // ω'F'(Θ): the single-scattering albedo times the truncated scattering matrix.
  Elements omega_f(double cos_theta) const;
};

// Builds the scaled layer for 2N streams: the aerosol is expanded and truncated at L = 2N − 1.
// Throws std::invalid_argument for negative depths, ρ outside [0, 0.5), ω outside [0, 1], or an
// aerosol depth without a table.
ScaledLayer scale_layer(const LayerOptics& optics, int streams_per_hemisphere);

// ωF of the untruncated layer (the true single-scattering source), τ the true extinction depth.
struct ExactLayer {
  double tau = 0;
  double rayleigh_weight = 0;  // τ_R/τ
  double aerosol_weight = 0;   // ω_A τ_A/τ
  double depolarization = 0;
  AngleTable aerosol;
  Elements omega_f(double cos_theta) const;
};
ExactLayer exact_layer(const LayerOptics& optics);

// A made-up polarizing aerosol for tests and benchmarks, not a measured one: every element is
// non-zero (F34 couples U and V). On `nodes` Gauss–Legendre nodes: F11 Henyey–Greenstein with
// asymmetry g, F12 = −f12·F11·sin²Θ/(1+cos²Θ), F22 = 0.95·F11, F33 = 0.9·F11·cos Θ,
// F34 = f34·F11·sin²Θ, F44 = 0.85·F11·cos Θ.
ScatteringMatrixTable synthetic_aerosol(double g, int nodes, double f12, double f34);

}  // namespace skypol::sky::vrte
