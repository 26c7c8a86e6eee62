// Vector radiative transfer in one homogeneous plane-parallel layer over a Lambertian ground, by
// doubling and adding per Fourier term in azimuth (de Haan, Bosma & Hovenier 1987, A&A 183, 371;
// Hovenier, van der Mee & Domke 2004, ch. 6). One solve gives every sun and view zenith angle in
// a list at once: those angles ride along as zero-weight quadrature points.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "sky/vrte/quadrature.h"  // gauss_legendre01
#include "sky/vrte/vrte_phase.h"

namespace skypol::sky::vrte {

// The accuracy knob is `streams`: N Gauss–Legendre nodes per hemisphere (2N streams). The aerosol
// is delta-M truncated at l = 2N − 1 and the azimuth series then has 2N terms; Rayleigh alone
// needs three (m = 0, 1, 2) whatever N. `initial_tau` bounds the thickness where doubling starts
// (from a layer correct to second order in it: the error of that start is ∝ its thickness squared).
struct SolverOptions {
  int streams = 8;                   // N ≥ 2
  int max_fourier = -1;              // highest m kept; −1: all the phase matrix has
  double initial_tau = 1e-6;         // doubling starts at τ/2^k ≤ this
  // The start: true, a layer correct to second order in its depth (error ∝ τ·initial_tau²);
  // false, single scattering alone (a low bias ∝ τ·initial_tau: ~1e-5 of I at 1e-6; tests).
  bool second_order_start = true;
  bool symmetric_doubling = true;    // light from below as the mirror image (false: computed; tests)
  int threads = 0;                   // 0: std::thread::hardware_concurrency()
  bool keep_gauss_matrices = false;  // keep the Gauss-node blocks (tests: reciprocity)
};

// The radiance field's Fourier coefficients per unit solar irradiance (the extraterrestrial
// irradiance on a surface ⟂ the sun, i.e. I/F in sr⁻¹): for a view at zenith cosine mu[i] and a
// sun at mu[j],
//   I = Σ_m I_m cos mΔφ,  Q = Σ_m Q_m cos mΔφ,  U = Σ_m U_m sin mΔφ,
// with Δφ the azimuth of the view direction minus the sun's, counter-clockwise seen from above
// (x towards y of a right-handed frame with z up). Q and U are in the meridian basis of the
// direction the observer looks along, d: e0 = ∂d/∂θ (θ the polar angle from the zenith; for a view
// upwards e0 points away from the zenith), e90 = d × e0 = ẑ × d/|ẑ × d| (docs/conventions.md).
// "down" is the diffuse sky seen from the ground looking up at zenith angle acos mu[i]; "up" is what
// an observer above the layer sees looking down at nadir angle acos mu[i]. Neither includes the
// direct sun.
struct FourierSolution {
  std::vector<double> mu;        // the nodes asked for (views and suns)
  int terms = 0;                 // m = 0 .. terms − 1
  std::vector<double> down, up;  // [((m·n + i)·n + j)·3 + k], k = I, Q, U
  std::vector<double> ground;    // [j]: the Lambertian ground's radiance (unpolarized)
  // The part of down/up that is the direct beam scattered once by the (truncated) layer, in the
  // same layout: what a table subtracts to keep only the smooth rest (Nakajima & Tanaka 1988).
  std::vector<double> ss_down, ss_up;
  double scaled_tau = 0;  // τ' after delta-M
  // With keep_gauss_matrices: the Gauss nodes and, per m, the total reflection at the top and the
  // diffuse transmission to the ground as (ns·N)² operators on radiance amplitudes (ns = 3 or 4
  // Stokes elements), before the sun's factor (2 − δ_m0)/2π.
  std::vector<double> gauss_mu, gauss_w;
  int stokes = 0;
  std::vector<Eigen::MatrixXd> gauss_reflection, gauss_transmission;

  double down_at(int m, std::size_t i, std::size_t j, int k) const {
    return down[((static_cast<std::size_t>(m) * mu.size() + i) * mu.size() + j) * 3 + static_cast<std::size_t>(k)];
  }
  double up_at(int m, std::size_t i, std::size_t j, int k) const {
    return up[((static_cast<std::size_t>(m) * mu.size() + i) * mu.size() + j) * 3 + static_cast<std::size_t>(k)];
  }
};

// Solves the layer for every pair (view mu[i], sun mu[j]). mu values in [0, 1]; 0 (the horizon)
// is allowed and gives the limits (a sun at the horizon lights nothing in a plane-parallel layer).
// albedo ∈ [0, 1]. Throws std::invalid_argument otherwise.
FourierSolution solve(const ScaledLayer& layer, double albedo, std::span<const double> mu,
                      const SolverOptions& options = {});

// The direct sun scattered once by a layer with scattering source ωF and depth tau, in closed
// form, in FourierSolution's convention (per unit solar irradiance, meridian basis, Δφ in
// radians): "down" at the ground looking up at mu, "up" at the top looking down at mu.
// Exact for any (mu, mu0, Δφ); mu = 0 and mu0 = 0 give the limits.
struct StokesIQU {
  double i = 0, q = 0, u = 0;
};
StokesIQU single_scattering(const ScaledLayer& layer, double mu, double mu0, double dphi, bool up);
StokesIQU single_scattering(const ExactLayer& layer, double mu, double mu0, double dphi, bool up);
// The geometric factor of that single scattering: StokesIQU = ωF(Θ)'s first column (rotated into the
// meridian basis) times this, i.e. μ0/(μ + μ0)·(1 − e^{−τ/μ − τ/μ0})/4π up and
// μ0(e^{−τ/μ} − e^{−τ/μ0})/(μ − μ0)/4π down.
double single_scattering_factor(double tau, double mu, double mu0, bool up);
// The same with cos Δφ and sin Δφ given (a unit pair), as the per-pixel path has them.
StokesIQU single_scattering(const ExactLayer& layer, double mu, double mu0, double cos_dphi, double sin_dphi, bool up);


}  // namespace skypol::sky::vrte
