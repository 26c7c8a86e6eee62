// Mie theory for homogeneous spheres, and its average over log-normal size distributions: the
// aerosol's cross sections and its scattering matrix table (atmosphere_optics.h) for the VRTE.
// Conventions are Bohren & Huffman (1983, "Absorption and Scattering of Light by Small
// Particles", ch. 4 and appendix A): time dependence exp(−iωt), refractive index m = n + ik with
// k ≥ 0 relative to the medium, S1 for E perpendicular and S2 for E parallel to the scattering plane.
// Wiscombe's MIEV0 (NCAR TN-140, 1979) uses exp(+iωt), m = n − ik: his S1, S2 are the complex
// conjugates of ours; every real quantity (Q, g, F11…F44) is the same.
#pragma once

#include <complex>
#include <span>
#include <vector>

#include "sky/vrte/atmosphere_optics.h"
#include "sky/vrte/quadrature.h"  // gauss_legendre, used with this header's tables

namespace skypol::sky {

// Number of terms of the partial-wave series: Wiscombe (1980, Appl. Opt. 19, 1505):
// x + 4x^⅓ + 1 for x ≤ 8, x + 4.05x^⅓ + 2 for 8 < x < 4200, x + 4x^⅓ + 2 above; at least 2.
int mie_term_count(double x);

// One sphere: efficiencies (cross section / πr²), asymmetry parameter and, on request, the
// amplitude functions at the given cos Θ.
struct MieSphere {
  double qext = 0.0;
  double qsca = 0.0;
  double qback = 0.0;  // backscattering efficiency, |Σ(2n+1)(−1)ⁿ(aₙ−bₙ)|²/x² (B&H sect. 4.6)
  double g = 0.0;      // ⟨cos Θ⟩
  std::vector<std::complex<double>> s1, s2;  // one per cos Θ asked for
};

// x = 2πr/λ > 0 (finite, ≤ 2·10⁴), m with Re m > 0, Im m ≥ 0, |m| ≤ 10 (the regime of the
// logarithmic-derivative downward recurrence started at max(N, |mx|) + 16, B&H's choice).
// Throws std::invalid_argument otherwise. cos_theta values must lie in [−1, 1].
MieSphere mie_sphere(std::complex<double> m, double x, std::span<const double> cos_theta = {});

// A log-normal number size distribution dN/d ln r ∝ exp(−(ln r − ln r_g)² / (2 ln²σ_g)):
// r_g is the median radius (= the mode of dN/d ln r, OPAC's "rmod"); the mode of dN/dr is
// r_g·exp(−ln²σ_g). Truncated to [r_min, r_max]; r_min = r_max = 0 picks the default range
// [r_g·σ_g^−4, r_g·σ_g^4·exp(2 ln²σ_g)] (±4 ln σ_g around the median of number, the upper end
// ±4 ln σ_g beyond the median of the area distribution, where the r²-weighted tail is < 3·10⁻⁵).
struct LogNormal {
  double median_radius_um = 0.1;
  double geometric_std = 2.0;  // σ_g > 1
  double r_min_um = 0.0;
  double r_max_um = 0.0;
};

// One component of an external mixture: particles of one refractive index and one distribution,
// with a number density in any unit (only the ratios between components matter). The density
// counts the whole, untruncated log-normal; particles outside [r_min, r_max] are left out of the
// integrals, not renormalised away (OPAC's convention, Hess et al. 1998: its truncated WASO and
// SOOT lose 3.7 % and 11 % of their number below r_min = 0.005 µm, optically nothing).
struct MieComponent {
  std::complex<double> m{1.5, 0.0};
  LogNormal size;
  double number_density = 1.0;
};

// Accuracy knobs. The defaults are what the named aerosol types need for a VRTE table: against a
// 30× finer reference, |ΔF11| ≤ 0.7 % and |ΔF12/F11| ≤ 0.005 at every node, |Δg| ≤ 2·10⁻⁴ and
// |ΔC_ext| ≤ 4·10⁻⁴ for the absorbing types; the sea-salt types (k = 10⁻⁸) keep ~2 % F11 noise
// in the backward hemisphere and 10⁻³ in g from their unresolvable ripple resonances
// (sky/README.md has the study).
struct MieQuadrature {
  // Gauss–Legendre nodes in cos Θ. 256 puts the node nearest the forward direction at 0.54° and
  // keeps the quadrature sum ½Σ wᵢF11ᵢ within 5·10⁻⁵ of 1 for every named type but desert, whose
  // coarse mode leaves 1.8·10⁻³ at 465 nm (2.7·10⁻³ at 400 nm) in the unresolved forward peak;
  // the cost is linear in it.
  int angle_nodes = 256;
  // Radius nodes: 8-point Gauss–Legendre panels in ln r, 8 steps wide, a step being ln_r_step where
  // particles are small and size_step/x where they are large (x ≳ 80): the interference and
  // polarization structure of F(Θ; x) at moderate x needs the fine ln r step (it sets the accuracy
  // above); the large particles' structure averages out at Δx = 1.
  double ln_r_step = 0.0125;
  double size_step = 1.0;
  // Far in the tail of the area-weighted distribution (below this fraction of its peak) the step
  // grows as 1/√(weight), up to 8×.
  double tail_fraction = 1e-2;
};

// Ensemble optics of a mixture at one wavelength.
struct MieEnsemble {
  double c_ext_um2 = 0.0;  // extinction cross section per particle (of the untruncated mixture), µm²
  double c_sca_um2 = 0.0;  // scattering cross section per particle, µm²
  double ssa = 1.0;        // c_sca / c_ext
  double g = 0.0;          // asymmetry parameter of the ensemble (from the partial-wave sums)
  int radius_nodes = 0;    // how many radii were evaluated (for timing reports)
  ScatteringMatrixTable table;  // F on Gauss–Legendre nodes, ½∫F11 dμ = 1 (analytically)
};

// Throws std::invalid_argument for an empty mixture, a bad component (σ_g ≤ 1, r_g ≤ 0, bad m,
// r_min ≥ r_max, negative density, all densities zero), wavelength ≤ 0 or fewer than 2 nodes.
MieEnsemble mie_ensemble(std::span<const MieComponent> mixture, double wavelength_nm,
                         const MieQuadrature& quadrature = {});
// Extinction and scattering only (no angles): what the Ångström exponent of a type needs.
MieEnsemble mie_ensemble_cross_sections(std::span<const MieComponent> mixture, double wavelength_nm,
                                        const MieQuadrature& quadrature = {});

// The default truncation range of a LogNormal whose r_min/r_max are 0 (see LogNormal).
LogNormal with_default_range(const LogNormal& size);


// ½ Σ wᵢ F11ᵢ: how well a table's own quadrature integrates its phase function (1 if resolved).
double quadrature_norm(const ScatteringMatrixTable& table);

}  // namespace skypol::sky
